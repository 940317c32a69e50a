// The cross-entropy search: finds a known minimum, never returns worse than the incumbent,
// keeps candidates in the box, and is deterministic for a random stream.
#include "planner/cem_search.h"

#include <cmath>
#include <vector>

#include "gtest/gtest.h"
#include "planner/testing/search_box.h"

namespace juggle {
namespace {

using ::juggle::testing::Box;

// Σ (x_d − c_d)² with c = (0.3, −0.2, 0.1, ...), evaluated candidate by candidate.
BatchCost Bowl(int* evaluations = nullptr) {
  return [evaluations](const std::vector<double>& x, int n, double, std::vector<double>* costs) {
    const int dim = static_cast<int>(x.size()) / n;
    for (int i = 0; i < n; ++i) {
      double c = 0;
      for (int d = 0; d < dim; ++d) {
        const double target = (d % 2 == 0 ? 0.3 : -0.2) / (1 + d / 2);
        c += std::pow(x[i * dim + d] - target, 2);
      }
      (*costs)[i] = c;
    }
    if (evaluations != nullptr) *evaluations += n;
    return absl::OkStatus();
  };
}

TEST(CemSearchTest, FindsTheMinimumOfAQuadraticBowl) {
  const SearchSpace space = Box(4, 1.0, 0.3);
  CemSettings settings;
  settings.samples = 64;
  settings.iterations = 12;
  settings.min_sigma_fraction = 0.001;
  Rng rng(3);
  int evaluations = 0;
  const CemResult r =
      *MinimizeCem(space, settings, {std::vector<double>(4, 0.0)}, &rng, Bowl(&evaluations));
  EXPECT_LT(r.best_cost, 1e-4);
  EXPECT_NEAR(r.best[0], 0.3, 0.01);
  EXPECT_NEAR(r.best[1], -0.2, 0.01);
  EXPECT_EQ(r.evaluations, evaluations);
  // Carried elites are not evaluated again.
  EXPECT_LT(evaluations, settings.samples * settings.iterations);
  ASSERT_EQ(r.iteration_best.size(), 12u);
  for (size_t i = 1; i < r.iteration_best.size(); ++i) {
    EXPECT_LE(r.iteration_best[i], r.iteration_best[i - 1]);
  }
}

TEST(CemSearchTest, NeverReturnsWorseThanTheIncumbent) {
  // Only the incumbent itself is good: every sampled candidate costs more.
  const std::vector<double> incumbent = {0.5, -0.5};
  const BatchCost spike = [&](const std::vector<double>& x, int n, double,
                              std::vector<double>* costs) {
    for (int i = 0; i < n; ++i) {
      const bool is_incumbent = x[2 * i] == incumbent[0] && x[2 * i + 1] == incumbent[1];
      (*costs)[i] = is_incumbent ? 1.0 : 2.0;
    }
    return absl::OkStatus();
  };
  Rng rng(4);
  const CemResult r = *MinimizeCem(Box(2, 1.0, 0.2), CemSettings{}, {incumbent}, &rng, spike);
  EXPECT_EQ(r.incumbent_cost, 1.0);
  EXPECT_EQ(r.best_cost, 1.0);
  EXPECT_EQ(r.best, incumbent);
}

TEST(CemSearchTest, EverySeedIsACandidateOfTheFirstIteration) {
  const std::vector<double> good = {0.3, -0.2};
  Rng rng(5);
  CemSettings settings;
  settings.iterations = 1;
  // The first seed is poor, the second sits on the minimum.
  const CemResult r =
      *MinimizeCem(Box(2, 1.0, 1e-9), settings, {{-0.9, 0.9}, good}, &rng, Bowl());
  EXPECT_EQ(r.best, good);
  EXPECT_EQ(r.best_cost, 0.0);
}

TEST(CemSearchTest, CandidatesStayInTheBox) {
  SearchSpace space = Box(3, 0.1, 5.0);  // a spread far wider than the box
  bool outside = false;
  const BatchCost check = [&](const std::vector<double>& x, int n, double,
                              std::vector<double>* costs) {
    for (double v : x) outside = outside || v < -0.1 || v > 0.1;
    for (int i = 0; i < n; ++i) (*costs)[i] = x[3 * i];
    return absl::OkStatus();
  };
  Rng rng(6);
  const CemResult r = *MinimizeCem(space, CemSettings{}, {{3.0, -3.0, 0.0}}, &rng, check);
  EXPECT_FALSE(outside);
  EXPECT_DOUBLE_EQ(r.best[0], -0.1);  // the cost falls with x_0: its lower bound
}

TEST(CemSearchTest, TheSameStreamGivesTheSamePlan) {
  const SearchSpace space = Box(5, 1.0, 0.3);
  Rng a(9), b(9), c(10);
  const CemResult ra = *MinimizeCem(space, CemSettings{}, {std::vector<double>(5, 0.0)}, &a, Bowl());
  const CemResult rb = *MinimizeCem(space, CemSettings{}, {std::vector<double>(5, 0.0)}, &b, Bowl());
  const CemResult rc = *MinimizeCem(space, CemSettings{}, {std::vector<double>(5, 0.0)}, &c, Bowl());
  EXPECT_EQ(ra.best, rb.best);
  EXPECT_EQ(ra.best_cost, rb.best_cost);
  EXPECT_NE(ra.best, rc.best);
}

TEST(CemSearchTest, StopsWhenAnIterationNoLongerImproves) {
  // A flat cost: the first iteration finds nothing better than the incumbent.
  const BatchCost flat = [](const std::vector<double>&, int n, double,
                            std::vector<double>* costs) {
    costs->assign(n, 1.0);
    return absl::OkStatus();
  };
  CemSettings settings;
  settings.iterations = 6;
  settings.converged_fraction = 0.01;
  Rng rng(8);
  const CemResult r = *MinimizeCem(Box(2, 1.0, 0.2), settings, {{0.0, 0.0}}, &rng, flat);
  EXPECT_EQ(r.iterations, 2);
  settings.converged_fraction = 0;
  Rng rng2(8);
  EXPECT_EQ((*MinimizeCem(Box(2, 1.0, 0.2), settings, {{0.0, 0.0}}, &rng2, flat)).iterations, 6);
}

// Batch sizes of a search without carried elites: each iteration's whole population.
std::vector<int> PopulationSizes(double decay, int samples, int iterations) {
  std::vector<int> sizes;
  int evaluations = 0;
  const BatchCost bowl = Bowl(&evaluations);
  const BatchCost record = [&](const std::vector<double>& x, int n, double bound,
                               std::vector<double>* costs) {
    sizes.push_back(n);
    return bowl(x, n, bound, costs);
  };
  CemSettings settings;
  settings.samples = samples;
  settings.iterations = iterations;
  settings.keep_elite_fraction = 0;
  settings.population_decay = decay;
  Rng rng(4);
  const CemResult r = *MinimizeCem(Box(3, 1.0, 0.3), settings, {{0.0, 0.0, 0.0}}, &rng, record);
  EXPECT_EQ(r.evaluations, evaluations);
  return sizes;
}

TEST(CemSearchTest, PopulationDecayShrinksEachIterationByTheFactorDownToTwiceTheElites) {
  // 64 / 1.25^i rounded: 64, 51.2, 40.96, 32.77, 26.21, 20.97.
  EXPECT_EQ(PopulationSizes(1.25, 64, 6), (std::vector<int>{64, 51, 41, 33, 26, 21}));
  // 64 / 4 = 16 is the floor (2 × 8 elites of the first 64); 4 would be below it.
  EXPECT_EQ(PopulationSizes(4, 64, 3), (std::vector<int>{64, 16, 16}));
  EXPECT_EQ(PopulationSizes(1, 64, 3), (std::vector<int>{64, 64, 64}));
}

TEST(CemSearchTest, StopsAfterTheFirstIterationWhoseBestIsGoodEnough) {
  CemSettings settings;
  settings.samples = 16;
  settings.iterations = 8;
  Rng full_rng(3);
  const CemResult full = *MinimizeCem(Box(2, 1.0, 0.3), settings, {{0.9, 0.9}}, &full_rng, Bowl());
  ASSERT_EQ(full.iterations, 8);
  // A threshold the full search crosses part-way: the stopped search ends at the first
  // iteration at or below it, with that iteration's best (the same draws up to there).
  const double threshold = full.iteration_best[3];
  int crossed = 0;
  while (full.iteration_best[crossed] > threshold) ++crossed;
  settings.stop_below = threshold;
  Rng rng(3);
  const CemResult stopped = *MinimizeCem(Box(2, 1.0, 0.3), settings, {{0.9, 0.9}}, &rng, Bowl());
  EXPECT_EQ(stopped.iterations, crossed + 1);
  EXPECT_LT(stopped.iterations, full.iterations);
  EXPECT_EQ(stopped.best_cost, full.iteration_best[crossed]);
  EXPECT_LE(stopped.best_cost, threshold);
  EXPECT_LT(stopped.evaluations, full.evaluations);
}

TEST(CemSearchTest, TellsTheBatchTheBestCostSoFar) {
  std::vector<double> bounds;
  const BatchCost record = [&](const std::vector<double>& x, int n, double bound,
                               std::vector<double>* costs) {
    bounds.push_back(bound);
    for (int i = 0; i < n; ++i) (*costs)[i] = 1.0 + std::abs(x[i]);
    return absl::OkStatus();
  };
  CemSettings settings;
  settings.iterations = 3;
  Rng rng(9);
  const CemResult r = *MinimizeCem(Box(1, 1.0, 0.5), settings, {{0.5}}, &rng, record);
  ASSERT_EQ(bounds.size(), 3u);
  EXPECT_TRUE(std::isinf(bounds[0]));
  EXPECT_EQ(bounds[1], r.iteration_best[0]);
  EXPECT_EQ(bounds[2], r.iteration_best[1]);
}

TEST(CemSearchTest, ExplorationSamplesUseTheInitialSpread) {
  // After the first iteration the elites sit together; exploring samples still go wide.
  double widest_last = 0;
  int calls = 0;
  const BatchCost cost = [&](const std::vector<double>& x, int n, double,
                             std::vector<double>* costs) {
    ++calls;
    for (int i = 0; i < n; ++i) {
      (*costs)[i] = std::abs(x[i]);
      if (calls == 3) widest_last = std::max(widest_last, std::abs(x[i]));
    }
    return absl::OkStatus();
  };
  CemSettings settings;
  settings.iterations = 3;
  settings.samples = 64;
  settings.min_sigma_fraction = 0.001;
  settings.explore_fraction = 0.5;
  Rng rng(10);
  ASSERT_TRUE(MinimizeCem(Box(1, 10.0, 1.0), settings, {{0.0}}, &rng, cost).ok());
  EXPECT_GT(widest_last, 0.8);
  settings.explore_fraction = 0;
  widest_last = 0;
  calls = 0;
  Rng rng2(10);
  ASSERT_TRUE(MinimizeCem(Box(1, 10.0, 1.0), settings, {{0.0}}, &rng2, cost).ok());
  EXPECT_LT(widest_last, 0.5);
}

// The bowl term by term, stopping once the sum so far reaches the bound (as a rollout prunes);
// every candidate's candidates and the terms summed are recorded.
BatchCost PruningBowl(std::vector<double>* seen, long* terms) {
  return [seen, terms](const std::vector<double>& x, int n, double bound,
                       std::vector<double>* costs) {
    const int dim = static_cast<int>(x.size()) / n;
    seen->insert(seen->end(), x.begin(), x.end());
    for (int i = 0; i < n; ++i) {
      double c = 0;
      for (int d = 0; d < dim; ++d) {
        const double target = (d % 2 == 0 ? 0.3 : -0.2) / (1 + d / 2);
        c += std::pow(x[i * dim + d] - target, 2);
        ++*terms;
        if (c >= bound) break;
      }
      (*costs)[i] = c;
    }
    return absl::OkStatus();
  };
}

TEST(CemSearchTest, PruningInChunksDrawsTheSameCandidatesAndFindsTheSameBestForFewerTerms) {
  CemSettings settings;
  settings.samples = 48;
  settings.iterations = 5;
  const SearchSpace space = Box(12, 2.0, 0.8);
  const std::vector<std::vector<double>> seeds = {std::vector<double>(12, 1.0)};
  std::vector<double> whole_seen, chunked_seen;
  long whole_terms = 0, chunked_terms = 0;
  Rng a(21), b(21);
  const CemResult whole = *MinimizeCem(space, settings, seeds, &a, PruningBowl(&whole_seen, &whole_terms));
  settings.prune_chunk = 4;
  const CemResult chunked =
      *MinimizeCem(space, settings, seeds, &b, PruningBowl(&chunked_seen, &chunked_terms));
  // Every iteration's elites are the same, so every later iteration draws the same candidates.
  EXPECT_EQ(chunked_seen, whole_seen);
  EXPECT_EQ(chunked.best, whole.best);
  EXPECT_EQ(chunked.best_cost, whole.best_cost);
  EXPECT_EQ(chunked.iteration_best, whole.iteration_best);
  EXPECT_EQ(chunked.incumbent_cost, whole.incumbent_cost);
  EXPECT_EQ(chunked.evaluations, whole.evaluations);
  // The first iteration has no bound in one call; in chunks it prunes after its first six.
  EXPECT_LT(chunked_terms, whole_terms * 0.95) << chunked_terms << " of " << whole_terms;
  // A chunk as large as the batch is one call.
  settings.prune_chunk = 48;
  std::vector<double> one_seen;
  long one_terms = 0;
  Rng c(21);
  MinimizeCem(space, settings, seeds, &c, PruningBowl(&one_seen, &one_terms)).IgnoreError();
  EXPECT_EQ(one_terms, whole_terms);
}

TEST(CemSearchTest, ACostErrorEndsTheSearchWithThatError) {
  int calls = 0;
  const BatchCost failing = [&](const std::vector<double>&, int n, double,
                                std::vector<double>* costs) {
    costs->assign(n, 1.0);
    return ++calls == 2 ? absl::InvalidArgumentError("rollout failed") : absl::OkStatus();
  };
  CemSettings settings;
  settings.iterations = 4;
  Rng rng(11);
  const absl::StatusOr<CemResult> r = MinimizeCem(Box(1, 1.0, 0.5), settings, {{0.0}}, &rng, failing);
  EXPECT_EQ(r.status(), absl::InvalidArgumentError("rollout failed"));
  EXPECT_EQ(calls, 2) << "no batch after the failing one";
}

}  // namespace
}  // namespace juggle
