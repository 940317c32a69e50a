// The pair shipped in policies/toss/ (docs/toss.md, docs/results.md) is what it claims to be:
// residuals on the base controllers, really applied. Its table row on the held-out seeds is
// checked end to end by tests/toss_cli_test.cc (ShippedPairReproducesItsTableRowOnEverySeed).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "common/eigen_policy.h"
#include "envs/policy_config.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/eval.h"
#include "envs/toss/juggler.h"
#include "gtest/gtest.h"

namespace juggle::toss {
namespace {

// One policy of the pair and the config it carries.
struct Shipped {
  LoadedConfig config;
  std::unique_ptr<EigenPolicy> policy;
};

Shipped LoadShipped(const std::string& role) {
  Shipped out;
  absl::StatusOr<PolicyAndConfig> file =
      LoadPolicyFile(testing::RepoPath("policies/toss/" + role + ".jglpolicy"));
  EXPECT_TRUE(file.ok()) << file.status();
  if (!file.ok()) return out;
  absl::StatusOr<EigenPolicy> policy = PolicyFromExport(file->policy);
  EXPECT_TRUE(policy.ok()) << policy.status();
  if (!policy.ok()) return out;
  out.config = file->config;
  out.policy = std::make_unique<EigenPolicy>(*std::move(policy));
  return out;
}

class ShippedTossPairTest : public ::testing::Test {
 protected:
  void SetUp() override {
    catcher_ = LoadShipped("catch");
    thrower_ = LoadShipped("throw");
    ASSERT_NE(catcher_.policy, nullptr);
    ASSERT_NE(thrower_.policy, nullptr);
    // The pair runs under the catch policy's config, as `juggle toss` runs it.
    ASSERT_TRUE(catcher_.config.run.toss().has_base()) << "the pair is residuals on the base";
    absl::StatusOr<std::shared_ptr<const TossSpec>> spec = SpecWithWind(catcher_.config, 0);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
  }
  TossPolicies Pair() const { return {catcher_.policy.get(), thrower_.policy.get()}; }
  JuggleRunResult Run(const std::string& pattern, TossPolicies policies, int throws) const {
    absl::StatusOr<Siteswap> p = Siteswap::Parse(pattern);
    EXPECT_TRUE(p.ok()) << p.status();
    absl::StatusOr<JuggleRunResult> r =
        RunOnce(spec_, JuggleSchedule(*p), policies, throws, /*seed=*/1001);
    EXPECT_TRUE(r.ok()) << r.status();
    return r.ok() ? *r : JuggleRunResult{};
  }

  Shipped catcher_, thrower_;
  std::shared_ptr<const TossSpec> spec_;
};

std::array<double, kTossJoints> RightTargets(const TossJuggler& juggler) {
  TossWorld::Snapshot s;
  juggler.world().Save(&s);
  return s.target[static_cast<int>(Hand::kRight)];
}

// Step by step on the held-out seed 1001, pattern 3: the right arm's PD targets are the base
// controllers' (the runtime stepped with an explicit zero residual) plus residual_scale × the
// mean action of the policy of its mode (catch or throw) on the observation the runtime shows it,
// and exactly what the runtime applies with that action given explicitly.
TEST_F(ShippedTossPairTest, TheArmsTargetsAreTheBaseTargetsPlusTheScaledPolicyAction) {
  JugglerOptions options;  // as the evaluation's runs (RunOnce)
  options.seed = 1001;
  absl::StatusOr<std::unique_ptr<TossJuggler>> juggler =
      TossJuggler::Create(spec_, JuggleSchedule(*Siteswap::Parse("3")), Pair(), options);
  ASSERT_TRUE(juggler.ok()) << juggler.status();
  const double scale = spec_->toss().base().residual_scale();
  ASSERT_GT(scale, 0);
  const float zero[kTossJoints] = {0, 0, 0, 0};
  int catching = 0, throwing = 0;
  double largest[2] = {0, 0};  // the largest residual applied (rad) catching, throwing
  for (int step = 0; step < 200; ++step) {
    SCOPED_TRACE(absl::StrCat("step ", step));
    TossJuggler& j = **juggler;
    const bool holding = j.world().held_by(Hand::kRight) >= 0;
    const bool policy_acts = j.HoldsThrow(Hand::kRight) ||
                             (!holding && j.IncomingBall(Hand::kRight) >= 0);
    float obs[kTossThrowObs];
    j.WriteObservation(Hand::kRight, obs);
    const RowMatrix action =
        (holding ? thrower_.policy : catcher_.policy)->MeanActions(obs, 1);
    std::unique_ptr<TossJuggler> base = j.Clone(), explicit_action = j.Clone();
    base->Step(zero);
    explicit_action->Step(policy_acts ? action.data() : zero);
    ASSERT_TRUE(j.Step());
    const std::array<double, kTossJoints> applied = RightTargets(j);
    ASSERT_EQ(applied, RightTargets(*explicit_action));
    if (!policy_acts) {
      ASSERT_EQ(applied, RightTargets(*base));
      continue;
    }
    (holding ? throwing : catching) += 1;
    for (int k = 0; k < kTossJoints; ++k) {
      const double residual = applied[k] - RightTargets(*base)[k];
      EXPECT_NEAR(residual, scale * std::clamp(action(0, k), -1.0f, 1.0f), 1e-12) << k;
      largest[holding] = std::max(largest[holding], std::abs(residual));
    }
  }
  EXPECT_GT(catching, 20);
  EXPECT_GT(throwing, 20);
  // Residuals, not rounding errors: milliradians at least, in both modes.
  EXPECT_GT(largest[0], 1e-3);
  EXPECT_GT(largest[1], 1e-3);
  std::printf("largest residual over 200 steps: catching %.4f rad (%d steps), throwing %.4f rad "
              "(%d steps)\n",
              largest[0], catching, largest[1], throwing);
}

// The outcome tells the pair from the base controllers alone, and each residual from its absence
// (same config, same held-out seed, 30 throws of 3 and of 531): the base alone releases at the
// planned velocity to rounding error (docs/results.md: < 1e-14 m/s), the throw residual moves
// the releases by millimetres per second (docs/results.md: 0.004–0.017 m/s per value); the catch
// residual leaves the base's throws exact but meets the balls with the arm elsewhere.
TEST_F(ShippedTossPairTest, ThePairsThrowsAndCatchesDifferFromTheBaseControllersAlone) {
  for (const char* pattern : {"3", "531"}) {
    SCOPED_TRACE(pattern);
    const JuggleRunResult base = Run(pattern, {}, 30);
    const JuggleRunResult pair = Run(pattern, Pair(), 30);
    const JuggleRunResult catch_only = Run(pattern, {catcher_.policy.get(), nullptr}, 30);
    const JuggleRunResult throw_only = Run(pattern, {nullptr, thrower_.policy.get()}, 30);
    for (const JuggleRunResult* r : {&base, &pair, &catch_only, &throw_only}) {
      EXPECT_EQ(r->throws, 30) << "every run juggles to its cap";
    }
    EXPECT_LT(base.mean_velocity_error, 1e-12);
    EXPECT_GT(pair.mean_velocity_error, 1e-3);
    EXPECT_LT(pair.mean_velocity_error, 0.02);
    EXPECT_GT(throw_only.mean_velocity_error, 1e-3);
    // The catch residual alone leaves the base's exact throws exact...
    EXPECT_LT(catch_only.mean_velocity_error, 1e-12);
    // ...and catches balls with the arm elsewhere than the base alone (the catching arm's state
    // at each catch; where the ball is caught is set by its own path and the catch radius).
    ASSERT_EQ(catch_only.throw_starts.size(), base.throw_starts.size());
    double arm_difference = 0;  // rad, rad/s
    for (size_t i = 0; i < base.throw_starts.size(); ++i) {
      for (int k = 0; k < kTossJoints; ++k) {
        arm_difference = std::max({arm_difference,
                                   std::abs(catch_only.throw_starts[i].angle[k] -
                                            base.throw_starts[i].angle[k]),
                                   std::abs(catch_only.throw_starts[i].speed[k] -
                                            base.throw_starts[i].speed[k])});
      }
    }
    EXPECT_GT(arm_difference, 1e-3);
    std::printf("%s: release-velocity error base %.2g, pair %.4f, throw residual alone %.4f, "
                "catch residual alone %.2g m/s; catch height error base %.4f, catch residual "
                "alone %.4f, pair %.4f m; the catch residual moves the arm at the catches by up "
                "to %.3f rad or rad/s\n",
                pattern, base.mean_velocity_error, pair.mean_velocity_error,
                throw_only.mean_velocity_error, catch_only.mean_velocity_error,
                base.mean_catch_height_error, catch_only.mean_catch_height_error,
                pair.mean_catch_height_error, arm_difference);
  }
}

}  // namespace
}  // namespace juggle::toss
