#include "worker/env_pool.h"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace juggle {

absl::StatusOr<std::unique_ptr<EnvPool>> EnvPool::Create(std::shared_ptr<const EnvSpec> spec,
                                                         int num_envs, int num_threads,
                                                         uint64_t seed, uint64_t worker) {
  if (num_envs < 1 || num_threads < 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        "env pool needs num_envs >= 1 and num_threads >= 1, got ", num_envs, " and ",
        num_threads));
  }
  std::unique_ptr<EnvPool> pool(new EnvPool(spec, std::min(num_threads, num_envs)));
  const int obs_dim = spec->obs_dim();
  for (int i = 0; i < num_envs; ++i) {
    pool->envs_.push_back(spec->NewEnv(Rng::ForStream(seed, worker, i)));
  }
  PoolStep& out = pool->out_;
  out.obs.assign(size_t(num_envs) * obs_dim, 0);
  out.final_obs.assign(size_t(num_envs) * obs_dim, 0);
  out.reward.assign(num_envs, 0);
  out.terminated.assign(num_envs, 0);
  out.truncated.assign(num_envs, 0);
  out.outcome.assign(num_envs, Outcome::kRunning);
  out.node.assign(num_envs, -1);
  out.events.reserve(4 * num_envs);
  pool->episode_return_.assign(num_envs, 0);
  pool->env_events_.resize(num_envs);
  for (auto& ev : pool->env_events_) ev.reserve(8);
  pool->finished_length_.assign(num_envs, 0);
  pool->finished_completions_.assign(num_envs, 0);
  pool->finished_juggles_.assign(num_envs, 0);
  return pool;
}

EnvPool::EnvPool(std::shared_ptr<const EnvSpec> spec, int num_threads)
    : spec_(std::move(spec)), walk_(&spec_->graph()), pool_(num_threads) {}

EnvPool::~EnvPool() = default;

void EnvPool::Reset() {
  for (int i = 0; i < num_envs(); ++i) {
    envs_[i]->Reset(walk_);
    envs_[i]->WriteObservation(out_.obs.data() + size_t(i) * obs_dim());
    episode_return_[i] = 0;
  }
}

void EnvPool::StepRange(int begin, int end) {
  const int obs_dim = spec_->obs_dim();
  for (int i = begin; i < end; ++i) {
    Env& env = *envs_[i];
    out_.node[i] = env.node();
    const StepResult r = env.Step(actions_ + size_t(i) * act_dim(), walk_);
    out_.reward[i] = r.reward;
    out_.outcome[i] = r.outcome;
    out_.terminated[i] = r.terminated();
    out_.truncated[i] = r.truncated();
    float* obs = out_.obs.data() + size_t(i) * obs_dim;
    if (r.truncated()) {
      env.WriteObservation(out_.final_obs.data() + size_t(i) * obs_dim);
    }
    env_events_[i] = env.events();
    if (r.outcome != Outcome::kRunning) {
      finished_length_[i] = env.steps();
      finished_completions_[i] = env.completions();
      finished_juggles_[i] = env.juggles();
      // The walk is read-only during the batch step, so resetting here is thread-safe; the
      // reset's own sampling does not create events.
      env.Reset(walk_);
    }
    env.WriteObservation(obs);
  }
}

void EnvPool::Step(const float* actions) {
  actions_ = actions;
  const int n = num_envs(), slices = pool_.threads();
  pool_.Run(slices, [this, n, slices](int slice, int) {
    StepRange(n * slice / slices, n * (slice + 1) / slices);
  });
  out_.events.clear();
  for (int i = 0; i < num_envs(); ++i) {
    const bool separate = i < separate_envs_;
    EpisodeCounters& stats = separate ? separate_stats_ : stats_;
    if (!separate) {
      const std::vector<EdgeEvent>& ev = env_events_[i];
      out_.events.insert(out_.events.end(), ev.begin(), ev.end());
    }
    episode_return_[i] += out_.reward[i];
    ++stats.steps;
    if (out_.outcome[i] != Outcome::kRunning) {
      ++stats.episodes;
      stats.return_sum += episode_return_[i];
      stats.length_sum += finished_length_[i];
      stats.completions_sum += finished_completions_[i];
      stats.juggles_sum += finished_juggles_[i];
      stats.CountOutcome(static_cast<int>(out_.outcome[i]));
      episode_return_[i] = 0;
    }
  }
  if (apply_events_locally_) {
    for (const EdgeEvent& e : out_.events) walk_.Apply(e).IgnoreError();
  }
}

EpisodeCounters EnvPool::TakeStats() {
  EpisodeCounters s = stats_;
  stats_ = EpisodeCounters();
  return s;
}

EpisodeCounters EnvPool::TakeSeparateStats() {
  EpisodeCounters s = separate_stats_;
  separate_stats_ = EpisodeCounters();
  return s;
}

}  // namespace juggle
