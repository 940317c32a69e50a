// `juggle dashboard`: a run directory rendered as the learner's dashboard page, in one
// self-contained HTML file (scripts, styles and data inlined; no server, no network), for a
// finished run or one still training. The data is the run's log (run_log.h) replayed into a
// DashboardState, the live dashboard's own state, and rendered by dashboard_json.h; runs logged
// before the "run" record existed get their name and control graph from their newest
// checkpoint's config, and their walk weights from its edge counts.
// Thread-compatible.
#ifndef JUGGLE_LEARNER_DASHBOARD_REPORT_H_
#define JUGGLE_LEARNER_DASHBOARD_REPORT_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "learner/dashboard_state.h"
#include "learner/run_log.h"

namespace juggle {

struct DashboardReport {
  std::string html;
  int iterations = 0, evaluations = 0;
  // What could not be shown and why (e.g. "no checkpoint: the control graph is not shown").
  std::vector<std::string> notes;
};

// `log`'s records told to a new DashboardState of `info`, in file order, as the training loop
// told them live; then the phase "finished". A checkpoint record sets the walk's weights and
// totals; iteration records carry no edge events.
std::unique_ptr<DashboardState> ReplayRunLog(const RunLog& log, const DashboardRunInfo& info);

// The report of `run_dir` (<run_dir>/metrics.jsonl, <run_dir>/checkpoints/). NOT_FOUND when
// the metrics file is missing; INVALID_ARGUMENT naming the line for a malformed record.
absl::StatusOr<DashboardReport> RenderRunDashboard(const std::string& run_dir);

// `juggle eval --json` output of `config` (its summary, node, edge and episode lines; any
// controller, the planner's included) as the dashboard page: the control graph coloured by
// the evaluation's success per node and edge (its edge lines as the walk's events), its
// juggles as one evaluation. INVALID_ARGUMENT naming file:line for a line that is not JSON or
// an edge the config's graph lacks; FAILED_PRECONDITION for a file without edge lines (an
// evaluation written before they existed, or a family without a control graph).
absl::StatusOr<DashboardReport> RenderEvalDashboard(const std::string& eval_json_path,
                                                    const LoadedConfig& config);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_REPORT_H_
