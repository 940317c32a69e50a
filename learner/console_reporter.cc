#include "learner/console_reporter.h"

#include <algorithm>
#include <cstdio>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "eval/summary.h"
#include "learner/in_run_eval.h"

namespace juggle {

std::string ProgressLine(const runlog::IterationRecord& r, const std::string& latest_eval) {
  std::string line = absl::StrFormat(
      "iter %5d  samples %9.0f  %7.0f samples/s  %5.1f sim-s/s  return %7.3f  ep_len %6.1f  "
      "juggles/ep %5.2f  lag %.2f  workers %d  %.2fs (wait %.2f, update %.2f)",
      r.iteration(), r.samples(), r.samples_per_s(), r.sim_s_per_s(), r.mean_return(),
      r.mean_episode_len(), r.juggles_per_episode(), r.policy_lag(), r.workers(),
      r.iteration_s(), r.wait_s(), r.update_s());
  if (r.demo_buffer() > 0) {  // planner-guided training
    absl::StrAppend(&line, absl::StrFormat("  | %s imit %.3g fresh %.3g (w %.3g) demos %.0f",
                                           r.cloning_only() ? "CLONE" : "ppo", r.imitation_loss(),
                                           r.imitation_fresh_error(), r.imitation_weight(),
                                           r.demo_buffer()));
    if (r.expert_episodes() > 0) {
      absl::StrAppend(&line, absl::StrFormat(" expert %.1f juggles/ep", r.expert_juggles_per_episode()));
    }
    if (r.expert_labels() > 0) {
      absl::StrAppend(&line, absl::StrFormat(" planner %.0f steps/label rescues %.2f",
                                             r.expert_rollout_steps() / r.expert_labels(),
                                             r.expert_rescues() / std::max(1.0, r.expert_replans())));
    }
    if (r.expert_proposal_tried() > 0) {
      absl::StrAppend(&line, absl::StrFormat(" policy chosen %.2f weight %.2f",
                                             r.expert_proposal_chosen() / r.expert_proposal_tried(),
                                             r.expert_proposal_weight_sum() / r.expert_proposal_tried()));
    }
  }
  if (!latest_eval.empty()) absl::StrAppend(&line, "  | ", latest_eval);
  return line;
}

absl::Status ConsoleReporter::OnIteration(const IterationEvent& event) {
  std::printf("%s\n", ProgressLine(event.record, latest_eval_).c_str());
  std::fflush(stdout);
  return absl::OkStatus();
}

absl::Status ConsoleReporter::OnEvaluation(const runlog::EvaluationRecord& record) {
  latest_eval_ = EvaluationShort(record);
  std::printf("%s: %s\n", latest_eval_.c_str(), SummaryLine(SummaryOf(record)).c_str());
  std::fflush(stdout);
  return absl::OkStatus();
}

}  // namespace juggle
