#include "learner/advantages.h"

#include <cmath>
#include <vector>

#include "gtest/gtest.h"

namespace juggle {
namespace {

struct Unroll {
  std::vector<float> rewards, values;
  std::vector<uint8_t> done, truncated;
  std::vector<float> bootstrap, truncated_values;
  AdvantageInputs Inputs(int num_unrolls) const {
    AdvantageInputs in;
    in.num_unrolls = num_unrolls;
    in.unroll_length = static_cast<int>(rewards.size()) / num_unrolls;
    in.rewards = rewards.data();
    in.values = values.data();
    in.done = done.data();
    in.truncated = truncated.data();
    in.bootstrap_values = bootstrap.data();
    in.truncated_values = truncated_values.data();
    return in;
  }
};

TEST(AdvantagesTest, MatchesHandComputedGae) {
  // T = 3, γ = 0.9, λ = 0.5, no episode end: bootstrap from V(s_3) = 4.
  Unroll u{{1, 2, 3}, {0.5, 1.0, 1.5}, {0, 0, 0}, {0, 0, 0}, {4}, {}};
  std::vector<float> ret;
  const std::vector<float> adv = ComputeAdvantages(u.Inputs(1), 0.9, 0.5, &ret);
  const double d2 = 3 + 0.9 * 4 - 1.5;    // 5.1
  const double d1 = 2 + 0.9 * 1.5 - 1.0;  // 2.35
  const double d0 = 1 + 0.9 * 1.0 - 0.5;  // 1.4
  const double a2 = d2, a1 = d1 + 0.45 * a2, a0 = d0 + 0.45 * a1;
  EXPECT_NEAR(adv[2], a2, 1e-5);
  EXPECT_NEAR(adv[1], a1, 1e-5);
  EXPECT_NEAR(adv[0], a0, 1e-5);
  EXPECT_NEAR(ret[0], a0 + 0.5, 1e-5);
}

TEST(AdvantagesTest, LambdaOneGivesMonteCarloReturnsOfTheRelease) {
  Unroll u{{1, 1, 1, 1}, {9, 9, 9, 9}, {0, 0, 0, 0}, {0, 0, 0, 0}, {10}, {}};
  std::vector<float> ret;
  ComputeAdvantages(u.Inputs(1), 0.995, 1.0, &ret);
  // R_t = Σ γ^k r + γ^(T−t) V(boot), independent of V(s_t).
  double r = 10;
  for (int t = 3; t >= 0; --t) {
    r = 1 + 0.995 * r;
    EXPECT_NEAR(ret[t], r, 1e-4) << "t=" << t;
  }
}

TEST(AdvantagesTest, TerminationCutsBootstrapAndTruncationBootstrapsFromFinalValue) {
  // Two unrolls of T = 2: the first terminates at t = 0, the second is truncated at t = 0.
  Unroll u{{1, 1, 1, 1}, {5, 5, 5, 5}, {1, 0, 0, 0}, {0, 0, 1, 0}, {7, 8}, {3}};
  std::vector<float> ret;
  const std::vector<float> adv = ComputeAdvantages(u.Inputs(2), 0.9, 0.95, &ret);
  EXPECT_NEAR(adv[0], 1 - 5, 1e-5);              // terminal: no future
  EXPECT_NEAR(adv[1], 1 + 0.9 * 7 - 5, 1e-5);    // unroll end: bootstrap 7
  EXPECT_NEAR(adv[2], 1 + 0.9 * 3 - 5, 1e-5);    // truncated: final value 3, chain cut
  EXPECT_NEAR(adv[3], 1 + 0.9 * 8 - 5, 1e-5);
}

}  // namespace
}  // namespace juggle
