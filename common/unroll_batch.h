// A batch of fixed-length unrolls in the layout the wire carries (worker -> learner), and its
// validation. Plain C++, no libtorch.
#ifndef JUGGLE_COMMON_UNROLL_BATCH_H_
#define JUGGLE_COMMON_UNROLL_BATCH_H_

#include <cstdint>
#include <vector>

#include "absl/status/status.h"

namespace juggle {

struct UnrollBatch {
  int num_unrolls = 0;     // U
  int unroll_length = 0;   // T
  int obs_dim = 0;
  int act_dim = 0;
  std::vector<float> obs;            // [U, T, obs_dim]: observation before each action
  std::vector<float> actions;        // [U, T, act_dim]
  std::vector<float> log_probs;      // [U, T]: behaviour log-probabilities
  std::vector<float> rewards;        // [U, T]
  std::vector<uint8_t> done;         // [U, T]: the episode terminated after this step
  std::vector<uint8_t> truncated;    // [U, T]: the episode hit its time limit after this step
  // For every truncated step, in (u, t) order: the last observation of that episode
  // (bootstrap target). [num_truncated, obs_dim]
  std::vector<float> truncated_obs;
  std::vector<float> bootstrap_obs;  // [U, obs_dim]: observation after the last step
  std::vector<int64_t> policy_version;  // [U]
  // Expert labels (planner-guided training, docs/learning.md); all empty when the batch has
  // none. labelled [U]: 1 for an unroll whose every step carries the expert's action for its
  // observation; labels [num_labelled, T, act_dim]: those actions, labelled unrolls in order.
  // expert_driven [U]: 1 for an unroll whose actions were the expert's rather than the
  // policy's (REQUIRES labelled): it feeds the demonstrations, never the PPO update.
  std::vector<uint8_t> labelled;
  std::vector<float> labels;
  std::vector<uint8_t> expert_driven;

  int64_t num_samples() const { return int64_t(num_unrolls) * unroll_length; }
  int num_truncated() const;
  int num_labelled() const;
  bool has_labels() const { return !labelled.empty(); }
  bool is_expert_driven(int u) const { return !expert_driven.empty() && expert_driven[u] != 0; }
};

// Checks the batch against the learner's dimensions and policy version. Nothing is modified.
//   INVALID_ARGUMENT: empty batch, any array of the wrong size, a flag other than 0/1, a step
//     both done and truncated, a non-finite number; labels whose sizes disagree with the
//     masks, an expert-driven unroll without labels.
//   FAILED_PRECONDITION: a policy version newer than `current_version` (unknown) or older than
//     current_version − max_policy_lag.
absl::Status ValidateUnrollBatch(const UnrollBatch& batch, int obs_dim, int act_dim,
                                 int64_t current_version, int64_t max_policy_lag);

// The batch without its expert-driven unrolls (what PPO trains on); the labels of the kept
// unrolls stay with them.
UnrollBatch WithoutExpertUnrolls(const UnrollBatch& batch);

}  // namespace juggle

#endif  // JUGGLE_COMMON_UNROLL_BATCH_H_
