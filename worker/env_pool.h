// EnvPool: N environments of one family (envs/env.h) stepped in lockstep on T threads (one
// shared mjModel, one mjData per env), with automatic reset. Env i draws from
// Rng::ForStream(seed, worker, i), and edge events are applied to the adaptive walk in env order
// after every batch step, so a run is bit-identical for a fixed seed whatever the thread count.
//
// Thread-safety: the pool's public methods must be called from one thread; the pool's own
// threads touch only their envs and read the walk, which is mutated only between steps.
#ifndef JUGGLE_WORKER_ENV_POOL_H_
#define JUGGLE_WORKER_ENV_POOL_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "absl/status/statusor.h"
#include "common/adaptive_walk.h"
#include "common/episode_counters.h"
#include "common/fork_join_pool.h"
#include "envs/env.h"

namespace juggle {

// Results of one batch step; buffers are preallocated and reused.
struct PoolStep {
  std::vector<float> obs;          // [num_envs, obs_dim]; after a reset: the new episode's first
  std::vector<float> reward;       // [num_envs]
  std::vector<uint8_t> terminated; // [num_envs] episode failed (includes kDiverged)
  std::vector<uint8_t> truncated;  // [num_envs] time limit
  std::vector<float> final_obs;    // [num_envs, obs_dim]; the last obs of a truncated episode
  std::vector<Outcome> outcome;    // [num_envs]
  std::vector<int32_t> node;       // [num_envs] node at the start of the step
  std::vector<EdgeEvent> events;   // this step's edge events, in env order
};

class EnvPool {
 public:
  // INVALID_ARGUMENT if num_envs < 1 or num_threads < 1.
  static absl::StatusOr<std::unique_ptr<EnvPool>> Create(std::shared_ptr<const EnvSpec> spec,
                                                         int num_envs, int num_threads,
                                                         uint64_t seed, uint64_t worker = 0);
  ~EnvPool();

  // Resets every env; output().obs holds the first observations.
  void Reset();
  // Steps every env with `actions` ([num_envs, act_dim]); finished envs are reset.
  // If apply_events_locally() (the default), the events update walk() afterwards.
  void Step(const float* actions);

  const PoolStep& output() const { return out_; }
  AdaptiveWalk* walk() { return &walk_; }
  void set_apply_events_locally(bool v) { apply_events_locally_ = v; }
  // Counters over the episodes finished since the last call (envs counted separately excluded).
  EpisodeCounters TakeStats();
  // Envs [0, n) are counted separately and their edge events are left out of output().events
  // and the walk: what an expert, not the policy, drives (planner-guided training).
  void set_separate_envs(int n) { separate_envs_ = n; }
  EpisodeCounters TakeSeparateStats();

  int num_envs() const { return static_cast<int>(envs_.size()); }
  int obs_dim() const { return spec_->obs_dim(); }
  int act_dim() const { return spec_->act_dim(); }
  const EnvSpec& spec() const { return *spec_; }
  Env& env(int i) { return *envs_[i]; }

 private:
  EnvPool(std::shared_ptr<const EnvSpec> spec, int num_threads);
  // Steps envs [begin, end) with actions_; touches only their state and outputs.
  void StepRange(int begin, int end);

  std::shared_ptr<const EnvSpec> spec_;
  AdaptiveWalk walk_;
  std::vector<std::unique_ptr<Env>> envs_;
  std::vector<double> episode_return_;
  // Per env, written by its thread during a step: events and the finished episode's length
  // and completions, captured before the automatic reset.
  std::vector<std::vector<EdgeEvent>> env_events_;
  std::vector<int> finished_length_;
  std::vector<int> finished_completions_;
  std::vector<int> finished_juggles_;
  PoolStep out_;
  EpisodeCounters stats_;
  int separate_envs_ = 0;
  EpisodeCounters separate_stats_;
  bool apply_events_locally_ = true;
  const float* actions_ = nullptr;

  // A batch step runs one job per thread, job j stepping the j-th of pool_.threads()
  // contiguous slices of the envs (whichever thread takes it: envs are independent).
  ForkJoinPool pool_;  // last member: its threads are joined before anything above goes
};

}  // namespace juggle

#endif  // JUGGLE_WORKER_ENV_POOL_H_
