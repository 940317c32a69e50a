#include "learner/dashboard_report.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "learner/dashboard_assets.h"
#include "learner/dashboard_json.h"
#include "learner/learner_state.h"
#include "learner/run_log.h"

namespace juggle {
namespace {

// The run's description and walk weights from its newest checkpoint (runs logged before the
// "run" record existed).
absl::StatusOr<runlog::CheckpointRecord> WalkFromCheckpoint(const std::string& run_dir,
                                                           DashboardRunInfo* info) {
  ASSIGN_OR_RETURN(LoadedCheckpoint checkpoint, LoadCheckpoint(run_dir));
  auto text = checkpoint.sections.find("run_config");
  if (text == checkpoint.sections.end()) {
    return absl::FailedPreconditionError(absl::StrCat(checkpoint.path, " carries no run config"));
  }
  // Older checkpoints store the text without the model: it names its model through config_path.
  ASSIGN_OR_RETURN(LoadedConfig config,
                   checkpoint.stored ? CheckpointConfig(checkpoint, nullptr)
                                     : ParseRunConfig(text->second, checkpoint.config_path));
  ASSIGN_OR_RETURN(std::shared_ptr<const EnvSpec> spec, CreateEnvSpec(config));
  *info = DescribeRun(config, *spec);
  runlog::CheckpointRecord walk;
  auto counts = checkpoint.sections.find("edge_counts");
  if (counts != checkpoint.sections.end() &&
      counts->second.size() == info->edges.size() * sizeof(double)) {
    std::vector<double> weights(info->edges.size());
    std::memcpy(weights.data(), counts->second.data(), counts->second.size());
    walk.mutable_weights()->Add(weights.begin(), weights.end());
  }
  return walk;
}

}  // namespace

std::unique_ptr<DashboardState> ReplayRunLog(const RunLog& log, const DashboardRunInfo& info) {
  auto state = std::make_unique<DashboardState>(info);
  std::vector<double> weights;
  for (const DashboardRunInfo::Edge& e : info.edges) weights.push_back(e.base_weight);
  WalkEventTotals none;
  none.Resize(static_cast<int>(info.edges.size()));
  // Replays cannot fail: DashboardState's hooks only record.
  for (const runlog::RunLogRecord& r : log.records) {
    if (r.has_iteration()) {
      state->OnIteration({r.iteration(), none, weights}).IgnoreError();
    } else if (r.has_evaluation()) {
      state->OnEvaluation(r.evaluation()).IgnoreError();
    } else if (r.has_checkpoint()) {
      if (r.checkpoint().weights_size() == static_cast<int>(weights.size())) {
        weights.assign(r.checkpoint().weights().begin(), r.checkpoint().weights().end());
      }
      state->OnCheckpoint(r.checkpoint()).IgnoreError();
    }
  }
  state->OnPhase({LoopPhase::kFinished, {}, 0});
  return state;
}

absl::StatusOr<DashboardReport> RenderRunDashboard(const std::string& run_dir) {
  const std::string path = RunLogPath(run_dir);
  ASSIGN_OR_RETURN(RunLog log, ReadRunLog(path));
  DashboardReport report;
  DashboardRunInfo info;
  if (const runlog::RunRecord* run = log.LastRun(); run != nullptr) {
    info = RunInfoOf(*run);
  } else {
    absl::StatusOr<runlog::CheckpointRecord> walk = WalkFromCheckpoint(run_dir, &info);
    if (walk.ok()) {
      // Its weights go first, as if a checkpoint record opened the log.
      runlog::RunLogRecord first;
      *first.mutable_checkpoint() = *std::move(walk);
      log.records.insert(log.records.begin(), std::move(first));
      report.notes.push_back(
          "the metrics file has no \"run\" record (an older run): name and graph from the "
          "newest checkpoint; per-edge event counts are not recorded");
    } else {
      report.notes.push_back(absl::StrCat("no run description (", walk.status().message(),
                                          "): the control graph is not shown"));
    }
  }
  report.iterations = log.CountOf(runlog::RunLogRecord::kIteration);
  report.evaluations = log.CountOf(runlog::RunLogRecord::kEvaluation);
  const std::unique_ptr<DashboardState> state = ReplayRunLog(log, info);
  const RecordedDashboard data = RecordedDashboardOf(
      *state, path,
      absl::StrCat(report.iterations, " iterations, ", report.evaluations, " evaluations"));
  report.html = InlineDashboardPage(absl::StrCat("window.JUGGLE_DATA = {\"status\": ", data.status,
                                                 ", \"history\": ", data.history,
                                                 ", \"evals\": ", data.evals, "};"));
  return report;
}

}  // namespace juggle
