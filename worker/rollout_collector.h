// Collects fixed-length unrolls from an EnvPool with an Eigen policy: one unroll per env per
// call, episodes continuing across calls (the env pool resets finished episodes). Produces the
// wire layout (UnrollBatch) a learner trains on. Thread-compatible.
#ifndef JUGGLE_WORKER_ROLLOUT_COLLECTOR_H_
#define JUGGLE_WORKER_ROLLOUT_COLLECTOR_H_

#include <atomic>
#include <cstdint>
#include <vector>

#include "common/eigen_policy.h"
#include "common/rng.h"
#include "common/unroll_batch.h"
#include "worker/env_pool.h"
#include "envs/labeller.h"

namespace juggle {

// Which envs of a worker's pool the expert labels and which it drives (ImitationConfig).
struct LabelPlan {
  Labeller* labeller = nullptr;  // null: no labels
  int label_envs = 0;            // envs [0, label_envs) get a label every step
  int expert_envs = 0;           // of those, [0, expert_envs) act with the label (+ noise)
  double expert_noise = 0;       // std of the Gaussian noise on expert-driven actions
};

class RolloutCollector {
 public:
  // REQUIRES: `pool` outlives the collector. Action noise for env i draws from its own stream
  // derived from (seed, worker, i).
  RolloutCollector(EnvPool* pool, int unroll_length, uint64_t seed, uint64_t worker = 0);

  // Expert labels from now on (REQUIRES: the labeller outlives the collector, label_envs ≤ the
  // pool's envs, expert_envs ≤ label_envs). The expert-driven envs are counted apart by the pool
  // (EnvPool::set_separate_envs) and their unrolls are flagged in the batch.
  void set_label_plan(const LabelPlan& plan);
  // Once *stop is set, Collect returns CANCELLED at its next step (the batch is then partial
  // and must be dropped): a labelled contribution can take minutes.
  void set_stop(const std::atomic<bool>* stop) { stop_ = stop; }

  // Runs unroll_length steps of every env with `policy` and writes them into `batch` (policy
  // version stamped from the policy). Edge events of these steps are appended to `events` if
  // given. The first call resets the pool. Errors: the labeller's (the batch is then partial).
  absl::Status Collect(const EigenPolicy& policy, UnrollBatch* batch,
               std::vector<EdgeEvent>* events = nullptr, std::vector<int32_t>* nodes = nullptr);
  // What the expert spent on labels since the previous call (zero without a labeller).
  ExpertCounters TakeExpertCounters();

 private:
  EnvPool* pool_;
  int unroll_length_;
  std::vector<Rng> rngs_;
  std::vector<float> actions_;
  LabelPlan labels_;
  const std::atomic<bool>* stop_ = nullptr;
  std::vector<Rng> expert_rngs_;  // noise of expert-driven actions, one stream per env
  bool started_ = false;
  int64_t labels_since_take_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_WORKER_ROLLOUT_COLLECTOR_H_
