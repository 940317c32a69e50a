// Bayesian optimization over a box of real variables: a Gaussian process on log(1 + cost)
// picks each next batch of candidates by expected improvement, so a search of a few variables
// needs far fewer evaluations than the cross-entropy method when each one is a rollout
// (docs/planner.md, "A model-based rescue"). The seeds and `initial` samples around the
// incumbent first, then batches chosen one candidate at a time (the model believes its own
// mean for the ones already chosen). The answer is the best candidate evaluated, never worse
// than the incumbent. Deterministic for a given random stream. Thread-compatible.
#ifndef JUGGLE_PLANNER_BAYES_SEARCH_H_
#define JUGGLE_PLANNER_BAYES_SEARCH_H_

#include <limits>
#include <vector>

#include "absl/status/statusor.h"
#include "common/rng.h"
#include "planner/cem_search.h"

namespace juggle {

struct BayesSettings {
  int evaluations = 96;  // most candidates simulated, the seeds included
  int initial = 8;       // samples around the incumbent (SearchSpace::sigma) before the model
  int batch = 4;         // candidates the model picks per call of the cost
  // Stop once the best cost is at or below this. -infinity: spend every evaluation.
  double stop_below = -std::numeric_limits<double>::infinity();
  int acquisition_points = 256;  // random points scored by expected improvement per pick
  // > 0 (with a finite stop_below that was reached): the answer is not the lowest cost but, of
  // the candidates at or below stop_below, the one with the lowest mean under a model with this
  // noise variance (standardized units): a plan in a wide dip rather than a single lucky one.
  double answer_noise = 0;
};

// Minimizes `cost` over `space` from `seeds` (each [dim], clamped into the box; the first is
// the incumbent). Variables whose box is a point or whose sigma is 0 are held at the
// incumbent's value. `cost` is always called with an infinite bound (the model needs every
// cost exactly). result.iterations counts the calls of `cost`; iteration_best the best after
// each. REQUIRES: at least one seed, settings.evaluations >= the seeds' count, batch >= 1.
absl::StatusOr<CemResult> MinimizeBayes(const SearchSpace& space, const BayesSettings& settings,
                                        const std::vector<std::vector<double>>& seeds, Rng* rng,
                                        const BatchCost& cost);

}  // namespace juggle

#endif  // JUGGLE_PLANNER_BAYES_SEARCH_H_
