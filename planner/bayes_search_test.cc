// The Bayesian search: reaches a bowl's bottom in fewer evaluations than the cross-entropy
// method, never returns worse than the incumbent, keeps candidates in the box and held
// variables at the incumbent's value, stops when good enough, and is deterministic.
#include "planner/bayes_search.h"

#include <cmath>
#include <vector>

#include "gtest/gtest.h"
#include "planner/testing/search_box.h"

namespace juggle {
namespace {

using ::juggle::testing::Box;

double Target(int d) { return (d % 2 == 0 ? 0.45 : -0.35) / (1 + d / 2); }

// 100 Σ (x_d − c_d)², as a kick's cost grows with its landing error; records every candidate.
// `exact`: every call must ask for exact costs (an infinite bound), as the model needs them.
BatchCost BayesBowl(std::vector<double>* seen = nullptr, bool exact = true) {
  return [seen, exact](const std::vector<double>& x, int n, double bound,
                       std::vector<double>* costs) {
    if (exact) {
      EXPECT_TRUE(std::isinf(bound));
    }
    const int dim = static_cast<int>(x.size()) / n;
    for (int i = 0; i < n; ++i) {
      double c = 0;
      for (int d = 0; d < dim; ++d) c += std::pow(x[i * dim + d] - Target(d), 2);
      (*costs)[i] = 100 * c;
    }
    if (seen != nullptr) seen->insert(seen->end(), x.begin(), x.end());
    return absl::OkStatus();
  };
}

TEST(BayesSearchTest, ReachesABowlsBottomInFewerEvaluationsThanTheCrossEntropyMethod) {
  const SearchSpace space = Box(5, 1.0, 0.3);
  const std::vector<std::vector<double>> seeds = {std::vector<double>(5, 0.0)};
  BayesSettings bayes;
  bayes.evaluations = 48;
  Rng rng(7);
  const CemResult b = *MinimizeBayes(space, bayes, seeds, &rng, BayesBowl());
  EXPECT_EQ(b.evaluations, 48);
  // The same budget for the cross-entropy method: 8 samples × 6 iterations.
  CemSettings cem;
  cem.samples = 8;
  cem.iterations = 6;
  cem.keep_elite_fraction = 0;
  Rng cem_rng(7);
  const CemResult c = *MinimizeCem(space, cem, seeds, &cem_rng, BayesBowl(nullptr, false));
  EXPECT_EQ(c.evaluations, 48);
  EXPECT_LT(b.best_cost, 0.5);  // within 0.07 of the bottom
  EXPECT_LT(b.best_cost, c.best_cost / 4);
  EXPECT_NEAR(b.best[0], Target(0), 0.07);
  EXPECT_NEAR(b.best[1], Target(1), 0.07);
  for (size_t i = 1; i < b.iteration_best.size(); ++i) {
    EXPECT_LE(b.iteration_best[i], b.iteration_best[i - 1]);
  }
}

TEST(BayesSearchTest, NeverReturnsWorseThanTheIncumbentAndKeepsCandidatesInTheBox) {
  SearchSpace space = Box(3, 0.5, 0.2);
  // A held variable (a point box) stays at the incumbent's value.
  space.lower[2] = space.upper[2] = 0.1;
  space.sigma[2] = 0;
  std::vector<double> seen;
  BayesSettings settings;
  settings.evaluations = 20;
  Rng rng(1);
  const std::vector<double> incumbent = {Target(0), Target(1), 0.1};
  const CemResult r = *MinimizeBayes(space, settings, {incumbent}, &rng, BayesBowl(&seen));
  EXPECT_EQ(r.best, incumbent);
  EXPECT_DOUBLE_EQ(r.best_cost, r.incumbent_cost);
  ASSERT_EQ(seen.size(), 20u * 3);
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_GE(seen[i], -0.5);
    EXPECT_LE(seen[i], 0.5);
    if (i % 3 == 2) {
      EXPECT_EQ(seen[i], 0.1);
    }
  }
}

TEST(BayesSearchTest, StopsOnceGoodEnoughAndCallsTheCostInBatches) {
  const SearchSpace space = Box(4, 1.0, 0.3);
  BayesSettings settings;
  settings.evaluations = 200;
  settings.initial = 6;
  settings.batch = 3;
  settings.stop_below = 5;
  Rng rng(2);
  const CemResult r =
      *MinimizeBayes(space, settings, {std::vector<double>(4, 0.0)}, &rng, BayesBowl());
  EXPECT_LE(r.best_cost, 5);
  EXPECT_GT(r.iteration_best[r.iteration_best.size() - 2], 5);  // the call before was not
  EXPECT_LT(r.evaluations, 200);
  EXPECT_EQ((r.evaluations - 7) % 3, 0);  // the seed and 6 samples, then batches of 3
  EXPECT_EQ(r.iterations, static_cast<int>(r.iteration_best.size()));
}

TEST(BayesSearchTest, IsDeterministicForARandomStreamAndSeedsAreCandidates) {
  const SearchSpace space = Box(5, 1.0, 0.3);
  const std::vector<double> good = {Target(0), Target(1), Target(2), Target(3), 0.2};
  BayesSettings settings;
  settings.evaluations = 24;
  Rng a(11), b(11);
  std::vector<double> seen_a, seen_b;
  const std::vector<std::vector<double>> seeds = {std::vector<double>(5, 0.0), good};
  const CemResult ra = *MinimizeBayes(space, settings, seeds, &a, BayesBowl(&seen_a));
  const CemResult rb = *MinimizeBayes(space, settings, seeds, &b, BayesBowl(&seen_b));
  EXPECT_EQ(seen_a, seen_b);
  EXPECT_EQ(ra.best, rb.best);
  EXPECT_EQ(std::vector<double>(seen_a.begin() + 5, seen_a.begin() + 10), good);
  EXPECT_LE(ra.best_cost, 100 * std::pow(0.2 - Target(4), 2));
}

// A wide basin (40 at its centre (0.5, 0.5), 60 at 0.5 from it) and a narrow dip (10 within
// 0.03 of (−0.5, −0.5)); 500 elsewhere.
double DipOrBasin(double x, double y) {
  const double wide = std::hypot(x - 0.5, y - 0.5), narrow = std::hypot(x + 0.5, y + 0.5);
  if (narrow < 0.03) return 10;
  if (wide < 0.5) return 40 + 20 * std::pow(wide / 0.5, 2);
  return 500;
}

TEST(BayesSearchTest, ASmoothedAnswerPrefersAWideBasinToASingleLuckyRollout) {
  const SearchSpace space = Box(2, 1.0, 0.15);
  const BatchCost cost = [](const std::vector<double>& x, int n, double,
                            std::vector<double>* costs) {
    for (int i = 0; i < n; ++i) (*costs)[i] = DipOrBasin(x[2 * i], x[2 * i + 1]);
    return absl::OkStatus();
  };
  // The basin's centre first (the samples go around it), the dip and its bad neighbours.
  const std::vector<std::vector<double>> seeds = {
      {0.5, 0.5}, {-0.5, -0.5}, {-0.4, -0.5}, {-0.6, -0.5}, {-0.5, -0.4}, {-0.5, -0.6}};
  BayesSettings settings;
  settings.evaluations = 24;
  settings.initial = 10;
  settings.stop_below = 100;
  Rng a(5), b(5);
  const CemResult lowest = *MinimizeBayes(space, settings, seeds, &a, cost);
  EXPECT_EQ(lowest.best, seeds[1]);
  EXPECT_EQ(lowest.best_cost, 10);
  settings.answer_noise = 0.3;
  const CemResult smoothed = *MinimizeBayes(space, settings, seeds, &b, cost);
  EXPECT_EQ(smoothed.evaluations, lowest.evaluations);  // the same search, another answer
  EXPECT_GE(smoothed.best_cost, 40);
  EXPECT_LE(smoothed.best_cost, 60);
  EXPECT_LT(std::hypot(smoothed.best[0] - 0.5, smoothed.best[1] - 0.5), 0.5);
}

}  // namespace
}  // namespace juggle
