// The evaluation tables `juggle eval` prints and writes as JSON lines (docs/results.md):
// - per node of the control graph (paper Fig. 6): visits, completions, success rate and the
//   outcomes that ended episodes there;
// - the robustness sweep (paper Table 1): a constant force on the ball along ±x, ±y, ±z at
//   increasing magnitudes, through the family's EnvFamily::SetConstantBallForce, and per
//   direction the largest force that keeps the median juggles at or above a threshold.
// Family-free. Thread-compatible.
#ifndef JUGGLE_EVAL_TABLES_H_
#define JUGGLE_EVAL_TABLES_H_

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/control_graph.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "eval/summary.h"

namespace juggle {

struct NodeRow {
  std::string node;                 // graph node name ("episode" for families without a graph)
  int visits = 0;
  int completions = 0;
  double success_rate = 0;          // completions / visits (0 without visits)
  std::map<std::string, int> endings;  // outcome name -> episodes that ended in this node
};

// One row per graph node (in graph order) over `episodes`' per-node counts.
std::vector<NodeRow> NodeTable(const std::vector<EpisodeResult>& episodes,
                               const ControlGraph& graph,
                               const std::vector<std::string>& outcome_names);
// The table as aligned text, one line per node, with a column per outcome that occurs.
std::string FormatNodeTable(const std::vector<NodeRow>& rows);

// One edge of the control graph over the episodes' walk events (EpisodeResult::edge_events).
struct EdgeRow {
  std::string from, to;  // node names
  int64_t chosen = 0, completed = 0, failed = 0;
};
// One row per graph edge, in graph order (none without a graph).
std::vector<EdgeRow> EdgeTable(const std::vector<EpisodeResult>& episodes,
                               const ControlGraph& graph);

struct ForceSweepOptions {
  std::vector<double> magnitudes = {0, 1, 2, 3, 4, 5};  // N, ascending; 0 is the baseline
  double min_median_juggles = 10;
  EpisodeOptions episodes;  // the same episodes (seeds) at every force
  // The 0 N evaluation, when the caller has already run these episodes without force (juggle
  // eval's plain evaluation): used for every direction's 0 N row instead of running it again.
  std::optional<EvalSummary> baseline;
};

struct ForceSweepRow {
  std::string direction;  // "+x", "-x", "+y", "-y", "+z", "-z"
  double force_n = 0;
  EvalSummary summary;
};

struct ForceSweepReport {
  std::vector<ForceSweepRow> rows;          // supported directions × magnitudes
  std::vector<std::string> directions;      // the supported ones, in sweep order (+x -x ... -z)
  // Per supported direction: the largest magnitude such that it and every smaller one keep
  // median juggles >= min_median_juggles; −1 when even the first magnitude does not.
  std::map<std::string, double> max_force_n;
  std::map<std::string, std::string> unsupported;  // direction -> the family's reason
};

// Runs the sweep on `config` (already an evaluation config: ConfigureForEvaluation). The
// zero force is run once and shared by every direction. `progress` (may be empty) receives a
// line per row. Errors: INVALID_ARGUMENT for no magnitudes or descending ones; a config the
// family cannot build; the factory's.
// `controllers` makes each swept config's controller (with the config's force: a planner plans
// with it).
absl::StatusOr<ForceSweepReport> RunForceSweep(
    const LoadedConfig& config, const ControllerFactory& controllers,
    const ForceSweepOptions& options, const std::function<void(const std::string&)>& progress);

// JSON objects (one line each, no trailing newline) for the JSON-lines outputs.
std::string SummaryJson(const EvalSummary& summary);
std::string NodeRowJson(const NodeRow& row);
// {"table": "edge", "from", "to", "chosen", "completed", "failed"}: what `juggle dashboard
// --eval` colours the graph by.
std::string EdgeRowJson(const EdgeRow& row);
// One episode: its index (its env stream), juggles, simulated seconds, return and ending, and
// the family's metrics of it (Env::AppendEpisodeMetrics, by name: football's kick per attempt).
std::string EpisodeJson(int episode, const EpisodeResult& e, double control_dt,
                        const std::vector<std::string>& outcome_names);
std::string ForceRowJson(const ForceSweepRow& row);
// A direction's result: the largest force that still passed.
std::string ForceLimitJson(const std::string& direction, double max_force_n,
                           double min_median_juggles);

}  // namespace juggle

#endif  // JUGGLE_EVAL_TABLES_H_
