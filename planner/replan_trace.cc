#include "planner/replan_trace.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle::planner {

std::string PlanningTask::DescribeDecision(const std::vector<double>& decision,
                                           const std::vector<double>& outcome) const {
  std::string out;
  if (!decision.empty()) {
    absl::StrAppend(&out, "  vars");
    for (double v : decision) absl::StrAppendFormat(&out, " %+.3g", v);
  }
  const std::vector<std::string> names = outcome_names();
  if (!outcome.empty()) absl::StrAppend(&out, "  outcome:");
  for (size_t i = 0; i < outcome.size(); ++i) {
    absl::StrAppendFormat(&out, " %s=%+.3g", i < names.size() ? names[i] : absl::StrCat(i),
                          outcome[i]);
  }
  return out;
}

std::string FormatReplanTrace(const PlanningTask& task, const EnvSpec& spec, int slot,
                              const ReplanReport& r) {
  std::string line =
      absl::StrFormat("  re-plan slot %d step %d node %d: cost %.4g -> %.4g (%d rollouts)", slot,
                      r.env_step, r.node, r.incumbent_cost, r.best_cost, r.evaluations);
  if (r.rescued) absl::StrAppend(&line, " rescue");
  if (r.light) absl::StrAppend(&line, " light");
  if (r.refined_out) absl::StrAppend(&line, " refined");
  if (r.predicts_failure) {
    absl::StrAppendFormat(&line, " ends %s at step %d",
                          spec.outcome_names()[static_cast<int>(r.predicted_end)],
                          r.predicted_end_step);
  }
  if (r.predicts_miss) absl::StrAppendFormat(&line, " misses a contact at step %d", r.predicted_end_step);
  absl::StrAppend(&line, task.DescribeDecision(r.decision, r.predicted_outcome));
  const std::vector<std::string> names = task.term_names();
  if (!r.terms.empty()) absl::StrAppend(&line, "  terms:");
  for (size_t i = 0; i < r.terms.size(); ++i) {
    absl::StrAppendFormat(&line, " %s=%.4g", i < names.size() ? names[i] : absl::StrCat(i),
                          r.terms[i]);
  }
  return line;
}

}  // namespace juggle::planner
