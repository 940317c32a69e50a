#include "learner/dashboard_report.h"

#include <cstring>
#include <optional>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "learner/dashboard_assets.h"
#include "learner/dashboard_json.h"
#include "learner/learner_state.h"

namespace juggle {
namespace {

// The run's description (and, into `file`, its walk weights) from its newest checkpoint.
absl::StatusOr<DashboardRunInfo> RunInfoFromCheckpoint(const std::string& run_dir,
                                                       MetricsFile* file) {
  ASSIGN_OR_RETURN(LoadedCheckpoint checkpoint, LoadCheckpoint(run_dir));
  auto text = checkpoint.sections.find("run_config");
  if (text == checkpoint.sections.end()) {
    return absl::FailedPreconditionError(absl::StrCat(checkpoint.path, " carries no run config"));
  }
  ASSIGN_OR_RETURN(LoadedConfig config, ParseRunConfig(text->second, checkpoint.config_path));
  ASSIGN_OR_RETURN(std::shared_ptr<const EnvSpec> spec, CreateEnvSpec(config));
  DashboardRunInfo info = DescribeRun(config, *spec);
  auto counts = checkpoint.sections.find("edge_counts");
  if (file->edge_counts.empty() && counts != checkpoint.sections.end() &&
      counts->second.size() == info.edges.size() * sizeof(double)) {
    file->edge_counts.resize(info.edges.size());
    std::memcpy(file->edge_counts.data(), counts->second.data(), counts->second.size());
  }
  return info;
}

}  // namespace

absl::StatusOr<DashboardReport> RenderRunDashboard(const std::string& run_dir) {
  const std::string path = run_dir + "/metrics.jsonl";
  ASSIGN_OR_RETURN(MetricsFile file, ParseMetricsFile(path));
  DashboardReport report;
  std::optional<DashboardRunInfo> info;
  if (!file.run) {
    absl::StatusOr<DashboardRunInfo> from_checkpoint = RunInfoFromCheckpoint(run_dir, &file);
    if (from_checkpoint.ok()) {
      info = std::move(*from_checkpoint);
      report.notes.push_back(
          "the metrics file has no \"run\" record (an older run): name and graph from the "
          "newest checkpoint; per-edge event counts are not recorded");
    } else {
      report.notes.push_back(absl::StrCat("no run description (", from_checkpoint.status().message(),
                                          "): the control graph is not shown"));
    }
  }
  const RecordedDashboard data = DashboardFromMetrics(file, path, info);
  report.iterations = static_cast<int>(file.iterations.size());
  report.evaluations = static_cast<int>(file.evaluations.size());
  report.html = InlineDashboardPage(absl::StrCat("window.JUGGLE_DATA = {\"status\": ", data.status,
                                                 ", \"history\": ", data.history,
                                                 ", \"evals\": ", data.evals, "};"));
  return report;
}

}  // namespace juggle
