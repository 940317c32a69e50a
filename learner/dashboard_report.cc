#include "learner/dashboard_report.h"

#include <cstring>
#include <map>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "common/file_io.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "learner/dashboard_assets.h"
#include "learner/dashboard_json.h"
#include "learner/learner_state.h"
#include "learner/run_log.h"
#include "nlohmann/json.hpp"

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

absl::StatusOr<DashboardReport> RenderEvalDashboard(const std::string& eval_json_path,
                                                    const LoadedConfig& config) {
  ASSIGN_OR_RETURN(std::shared_ptr<const EnvSpec> spec, CreateEnvSpec(config));
  const DashboardRunInfo info = DescribeRun(config, *spec);
  std::map<std::pair<std::string, std::string>, int> edge_of;
  for (size_t e = 0; e < info.edges.size(); ++e) {
    edge_of[{info.nodes[info.edges[e].from].name, info.nodes[info.edges[e].to].name}] =
        static_cast<int>(e);
  }
  ASSIGN_OR_RETURN(std::string text, ReadFile(eval_json_path));
  WalkEventTotals totals;
  totals.Resize(static_cast<int>(info.edges.size()));
  runlog::EvaluationRecord eval;
  eval.set_event("eval");
  nlohmann::json summary = nlohmann::json::object();
  std::map<std::string, std::pair<int64_t, int64_t>> node_rows;  // name -> (visits, completions)
  int edge_lines = 0, line_number = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_number;
    if (line.empty()) continue;
    const auto where = [&] { return absl::StrCat(eval_json_path, ":", line_number, ": "); };
    const nlohmann::json row = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (row.is_discarded() || !row.is_object()) {
      return absl::InvalidArgumentError(absl::StrCat(where(), "not a JSON object"));
    }
    const std::string table = row.value("table", "");
    try {
      if (table == "edge") {
        const std::string from = row.at("from"), to = row.at("to");
        auto it = edge_of.find({from, to});
        if (it == edge_of.end()) {
          return absl::InvalidArgumentError(absl::StrCat(
              where(), "edge ", from, " -> ", to, " is not in the graph of ", config.config_path));
        }
        totals.chosen[it->second] += row.at("chosen").get<int64_t>();
        totals.completed[it->second] += row.at("completed").get<int64_t>();
        totals.failed[it->second] += row.at("failed").get<int64_t>();
        ++edge_lines;
      } else if (table == "node") {
        node_rows[row.at("node").get<std::string>()] = {row.at("visits").get<int64_t>(),
                                                        row.at("completions").get<int64_t>()};
      } else if (table == "summary") {
        summary = row;
        eval.set_episodes(row.value("episodes", 0));
        eval.set_median_juggles(row.value("median_juggles", 0.0));
        eval.set_p10_juggles(row.value("p10_juggles", 0.0));
        eval.set_p90_juggles(row.value("p90_juggles", 0.0));
        eval.set_mean_juggles(row.value("mean_juggles", 0.0));
        eval.set_frac_juggles_ge_10(row.value("frac_juggles_ge_10", 0.0));
        eval.set_frac_juggles_ge_20(row.value("frac_juggles_ge_20", 0.0));
        eval.set_mean_return(row.value("mean_return", 0.0));
        eval.set_mean_episode_s(row.value("mean_episode_s", 0.0));
        eval.set_mean_completions(row.value("mean_completions", 0.0));
        if (row.contains("outcomes") && row["outcomes"].is_object()) {
          for (const auto& [name, count] : row["outcomes"].items()) {
            (*eval.mutable_outcomes())[name] = count.get<int>();
          }
        }
      } else if (table == "episode") {
        eval.add_juggles(row.at("juggles").get<int>());
      }
    } catch (const nlohmann::json::exception& e) {
      return absl::InvalidArgumentError(absl::StrCat(where(), "a ", table, " line: ", e.what()));
    }
  }
  if (edge_lines == 0) {
    return absl::FailedPreconditionError(absl::StrCat(
        eval_json_path, " has no edge lines: written by an older `juggle eval`, or the family "
        "has no control graph; run the evaluation again with --json"));
  }
  DashboardState state(info);
  std::vector<double> weights;
  for (const DashboardRunInfo::Edge& e : info.edges) weights.push_back(e.base_weight);
  runlog::IterationRecord none;
  RETURN_IF_ERROR(state.OnIteration({none, totals, weights}));
  RETURN_IF_ERROR(state.OnEvaluation(eval));
  state.OnPhase({LoopPhase::kFinished, {}, 0});
  DashboardReport report;
  report.evaluations = 1;
  report.notes.push_back(
      "an evaluation, not a training run: the page shows its summary and the control graph "
      "coloured by its success per node and edge");
  const RecordedDashboard data = RecordedDashboardOf(
      state, eval_json_path, absl::StrCat("evaluation of ", eval.episodes(), " episodes"));
  // The nodes as the evaluation's own per-node table has them (the episodes' starts included),
  // not only the arrivals through edges.
  nlohmann::json status = nlohmann::json::parse(data.status);
  for (nlohmann::json& node : status["graph"]["nodes"]) {
    auto it = node_rows.find(node["name"].get<std::string>());
    if (it == node_rows.end()) continue;
    const auto [visits, completions] = it->second;
    node["entered"] = visits;
    node["completed"] = completions;
    node["failed"] = visits - completions;
    node["success"] = visits > 0 ? nlohmann::json(static_cast<double>(completions) / visits)
                                 : nlohmann::json(nullptr);
    node["recent_success"] = nullptr;
  }
  summary["source"] = absl::StrCat(eval_json_path, " (", config.config_path, ")");
  report.html = InlineDashboardPage(absl::StrCat(
      "window.JUGGLE_DATA = {\"status\": ", status.dump(), ", \"history\": ", data.history,
      ", \"evals\": ", data.evals, ", \"evaluation\": ", summary.dump(), "};"));
  return report;
}

}  // namespace juggle
