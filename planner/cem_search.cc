#include "planner/cem_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace juggle {
namespace {

struct Scored {
  std::vector<double> x;
  double cost = 0;
};

void ClampInto(const SearchSpace& space, double* x) {
  for (int d = 0; d < space.dim(); ++d) x[d] = std::clamp(x[d], space.lower[d], space.upper[d]);
}

// Candidates of iteration `it` (carried elites included): iCEM's decayed population, never
// below twice the elites of a full first iteration.
int IterationSamples(const CemSettings& settings, int it) {
  if (settings.population_decay <= 1 || it == 0) return settings.samples;
  const int first_elites = std::max(
      2, static_cast<int>(std::lround(settings.elite_fraction * settings.samples)));
  const int decayed = static_cast<int>(
      std::lround(settings.samples * std::pow(settings.population_decay, -it)));
  return std::max(decayed, std::min(settings.samples, 2 * first_elites));
}

// Elites of an iteration whose pool (carried and fresh) holds `pool_size` candidates.
int EliteCount(const CemSettings& settings, int pool_size) {
  return std::clamp(
      static_cast<int>(std::lround(settings.elite_fraction * static_cast<double>(pool_size))),
      std::min(2, pool_size), pool_size);
}

// Scores the `fresh` candidates of `batch` in calls of settings.prune_chunk. Before each call
// the bound is the lowest of `before` and the `matter`-th lowest cost scored so far (`scored`
// starts with the carried elites' costs): a candidate at or above it has at least `matter`
// candidates ahead of it in the stable sort (they come earlier in the pool), and a pruned
// candidate's cost is never below the bound, so the first `matter` of the pool are the same
// as with one call.
absl::Status ScoreInChunks(const CemSettings& settings, const std::vector<double>& batch, int dim,
                           int fresh, double before, int matter, std::vector<double> scored,
                           const BatchCost& cost, std::vector<double>* costs) {
  costs->assign(fresh, 0.0);
  if (settings.prune_chunk <= 0 || settings.prune_chunk >= fresh) {
    return cost(batch, fresh, before, costs);
  }
  std::vector<double> chunk, chunk_costs;
  for (int start = 0; start < fresh; start += settings.prune_chunk) {
    const int n = std::min(settings.prune_chunk, fresh - start);
    double bound = before;
    if (static_cast<int>(scored.size()) >= matter) {
      std::nth_element(scored.begin(), scored.begin() + (matter - 1), scored.end());
      bound = std::min(bound, scored[matter - 1]);
    }
    chunk.assign(batch.begin() + static_cast<size_t>(start) * dim,
                 batch.begin() + static_cast<size_t>(start + n) * dim);
    chunk_costs.assign(n, 0.0);
    if (absl::Status s = cost(chunk, n, bound, &chunk_costs); !s.ok()) return s;
    std::copy(chunk_costs.begin(), chunk_costs.end(), costs->begin() + start);
    scored.insert(scored.end(), chunk_costs.begin(), chunk_costs.end());
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<CemResult> MinimizeCem(const SearchSpace& space, const CemSettings& settings,
                      const std::vector<std::vector<double>>& seeds, Rng* rng,
                      const BatchCost& cost) {
  const int dim = space.dim();
  std::vector<double> mean = seeds.front();
  mean.resize(dim, 0.0);
  ClampInto(space, mean.data());
  std::vector<double> sigma = space.sigma;
  CemResult result;
  std::vector<Scored> carried;
  std::vector<double> batch;
  std::vector<double> costs;
  for (int it = 0; it < settings.iterations; ++it) {
    const int samples = IterationSamples(settings, it);
    // New candidates: the mean first (the incumbent in the first iteration), the other seeds
    // in the first iteration, then samples.
    const int fresh = std::max(1, samples - static_cast<int>(carried.size()));
    batch.assign(static_cast<size_t>(fresh) * dim, 0.0);
    std::copy(mean.begin(), mean.end(), batch.begin());
    int given = 1;
    if (it == 0) {
      for (size_t s = 1; s < seeds.size() && given < fresh; ++s, ++given) {
        double* x = batch.data() + static_cast<size_t>(given) * dim;
        std::copy_n(seeds[s].begin(), dim, x);
        ClampInto(space, x);
      }
    }
    const int exploring = static_cast<int>(std::lround(settings.explore_fraction * (fresh - given)));
    for (int i = given; i < fresh; ++i) {
      double* x = batch.data() + static_cast<size_t>(i) * dim;
      const std::vector<double>& spread = i < fresh - exploring ? sigma : space.sigma;
      for (int d = 0; d < dim; ++d) x[d] = mean[d] + spread[d] * rng->Normal();
      ClampInto(space, x);
    }
    const double before = it == 0 ? std::numeric_limits<double>::infinity() : result.best_cost;
    // What the iteration's choices read: its elites, in the last iteration the best alone.
    const int pool_size = static_cast<int>(carried.size()) + fresh;
    const int matter = it + 1 == settings.iterations ? 1 : EliteCount(settings, pool_size);
    std::vector<double> scored;
    for (const Scored& c : carried) scored.push_back(c.cost);
    if (absl::Status s =
            ScoreInChunks(settings, batch, dim, fresh, before, matter, std::move(scored), cost, &costs);
        !s.ok()) {
      return s;
    }
    result.evaluations += fresh;
    result.iterations = it + 1;
    if (it == 0) {
      result.incumbent_cost = costs[0];
      result.best.assign(mean.begin(), mean.end());
      result.best_cost = costs[0];
    }
    std::vector<Scored> pool = std::move(carried);
    for (int i = 0; i < fresh; ++i) {
      pool.push_back({std::vector<double>(batch.begin() + static_cast<size_t>(i) * dim,
                                          batch.begin() + static_cast<size_t>(i + 1) * dim),
                      costs[i]});
    }
    // Stable: ties keep the carried elites, then candidate order (determinism).
    std::stable_sort(pool.begin(), pool.end(),
                     [](const Scored& a, const Scored& b) { return a.cost < b.cost; });
    if (pool.front().cost < result.best_cost) {
      result.best = pool.front().x;
      result.best_cost = pool.front().cost;
    }
    result.iteration_best.push_back(result.best_cost);
    if (result.best_cost <= settings.stop_below) break;
    if (it > 0 && settings.converged_fraction > 0 &&
        before - result.best_cost <= settings.converged_fraction * std::abs(result.best_cost)) {
      break;
    }
    const int elites = EliteCount(settings, static_cast<int>(pool.size()));
    for (int d = 0; d < dim; ++d) {
      double m = 0;
      for (int e = 0; e < elites; ++e) m += pool[e].x[d];
      m /= elites;
      double v = 0;
      for (int e = 0; e < elites; ++e) v += (pool[e].x[d] - m) * (pool[e].x[d] - m);
      mean[d] = m;
      sigma[d] = std::max(std::sqrt(v / elites), settings.min_sigma_fraction * space.sigma[d]);
    }
    const int keep = static_cast<int>(std::lround(settings.keep_elite_fraction * elites));
    pool.resize(std::min<size_t>(pool.size(), keep));
    carried = std::move(pool);
  }
  return result;
}

}  // namespace juggle
