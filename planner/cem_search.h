// The cross-entropy method over a box of real variables, in the iCEM form: the incumbent is
// always a candidate, a share of each iteration's elites is carried into the next one (their
// costs reused), and the best candidate ever seen is the answer, so the result is never worse
// than the incumbent. Deterministic for a given random stream. Thread-compatible; the batch
// cost function may evaluate its candidates in parallel.
#ifndef JUGGLE_PLANNER_CEM_SEARCH_H_
#define JUGGLE_PLANNER_CEM_SEARCH_H_

#include <functional>
#include <limits>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/rng.h"

namespace juggle {

struct SearchSpace {
  // Per variable: the box and the initial spread (standard deviation) of samples.
  std::vector<double> lower, upper, sigma;
  int dim() const { return static_cast<int>(lower.size()); }
};

struct CemSettings {
  int samples = 32;                 // candidates per iteration (carried elites included)
  int iterations = 5;
  double elite_fraction = 0.125;    // at least 2 elites
  double keep_elite_fraction = 0.3; // of the elites, carried into the next iteration
  double min_sigma_fraction = 0.1;  // spread floor, relative to SearchSpace::sigma
  // Share of each iteration's fresh samples drawn with the initial spread (around the current
  // mean), so the search keeps looking beyond a collapsed spread.
  double explore_fraction = 0;
  // Stop after an iteration that lowers the best cost by less than this fraction of it (0:
  // always run every iteration).
  double converged_fraction = 0;
  // Stop after an iteration whose best cost is at or below this (good enough: a rescue search
  // ends once out of trouble). -infinity: never.
  double stop_below = -std::numeric_limits<double>::infinity();
  // iCEM's population decay: iteration i draws samples / population_decay^i candidates (carried
  // elites included), never fewer than twice the first iteration's elites. 1: every iteration
  // draws `samples`.
  double population_decay = 1;
  // Candidates per call of the batch cost (0: each iteration's fresh candidates in one call).
  // Between calls the bound tightens to the cost that the candidates scored so far in the
  // iteration (carried elites included) put on the elites — the best alone in the last
  // iteration: a candidate at or above it can be neither, so the search's choices are those
  // of whole batches, bit for bit, and a pruning cost simulates less.
  int prune_chunk = 0;
};

// Writes the costs of `n` candidates (row-major [n, dim] in `candidates`) to costs[0..n).
// `bound` is the best cost found before this batch (infinity for the first), or lower with
// CemSettings::prune_chunk: a candidate known to cost at least that much may be given any
// cost >= bound (it can become neither the best nor an elite), so its evaluation may stop
// early; the value must still be deterministic. An error (e.g. a
// rollout that could not run) ends the search with that error.
using BatchCost = std::function<absl::Status(const std::vector<double>& candidates, int n,
                                             double bound, std::vector<double>* costs)>;

struct CemResult {
  std::vector<double> best;          // [dim]
  double best_cost = 0;
  double incumbent_cost = 0;         // the cost of the incumbent as given
  int evaluations = 0;               // candidates simulated
  int iterations = 0;                // run (fewer than asked when converged)
  std::vector<double> iteration_best;  // best cost so far after each iteration
};

// Minimizes `cost` over `space` starting from `seeds` (each [dim], clamped into the box): the
// first is the incumbent (the initial mean); every seed is a candidate of the first iteration.
// REQUIRES: at least one seed, space's vectors have equal sizes, lower <= upper,
// settings.samples >= seeds.size() and settings.iterations >= 1. Errors: the cost's.
absl::StatusOr<CemResult> MinimizeCem(const SearchSpace& space, const CemSettings& settings,
                      const std::vector<std::vector<double>>& seeds, Rng* rng,
                      const BatchCost& cost);

}  // namespace juggle

#endif  // JUGGLE_PLANNER_CEM_SEARCH_H_
