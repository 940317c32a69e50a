// What the expert of planner-guided training spent on its labels (issue 48's loop view): a
// worker's labeller accumulates them, each contribution carries them (common/chunk_codec.h),
// and the learner sums them per iteration (proto/run_log.proto).
#ifndef JUGGLE_COMMON_EXPERT_COUNTERS_H_
#define JUGGLE_COMMON_EXPERT_COUNTERS_H_

#include <cmath>
#include <cstdint>

namespace juggle {

struct ExpertCounters {
  int64_t labels = 0;           // labelled env steps
  int64_t replans = 0;
  int64_t rollout_steps = 0;    // control steps its rollouts simulated
  int64_t rescues = 0;          // re-plans that ran the wider second search
  int64_t proposal_tried = 0;   // re-plans that tried the learned proposal alone
  int64_t proposal_chosen = 0;  // ... and chose it
  double proposal_weight_sum = 0;  // the chosen plans' weight of the proposal, over those

  void Add(const ExpertCounters& o) {
    labels += o.labels;
    replans += o.replans;
    rollout_steps += o.rollout_steps;
    rescues += o.rescues;
    proposal_tried += o.proposal_tried;
    proposal_chosen += o.proposal_chosen;
    proposal_weight_sum += o.proposal_weight_sum;
  }
  bool valid() const {
    return labels >= 0 && replans >= 0 && rollout_steps >= 0 && rescues >= 0 &&
           rescues <= replans && proposal_tried >= 0 && proposal_chosen >= 0 &&
           proposal_chosen <= proposal_tried && proposal_tried <= replans &&
           std::isfinite(proposal_weight_sum) && proposal_weight_sum >= 0 &&
           proposal_weight_sum <= double(proposal_tried);
  }
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_EXPERT_COUNTERS_H_
