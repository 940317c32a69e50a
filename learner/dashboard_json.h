// The dashboard's JSON documents (docs/dashboard.md has the schema), built with nlohmann/json:
//   /api/status   the run, its state, progress, throughput, workers, the control graph with the
//                 walk's weights and per-edge/per-node success, the latest evaluation;
//   /api/history  the iteration reports (bounded, thinned over the whole run);
//   /api/evals    the in-run evaluations.
// The live learner builds them from DashboardState, WorkerRegistry and Metrics; `juggle
// dashboard` builds the same documents from a run's metrics.jsonl (ParseMetricsFile), so one
// page renders both. Also the metrics.jsonl records this adds: "event": "run" (the run and its
// graph, once at start) and "event": "walk" (edge weights and event totals, every checkpoint).
// Pure functions; thread-safe.
#ifndef JUGGLE_LEARNER_DASHBOARD_JSON_H_
#define JUGGLE_LEARNER_DASHBOARD_JSON_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/metrics.h"
#include "learner/dashboard_state.h"
#include "learner/worker_registry.h"

namespace juggle {

// One worker row. `status`: "ok"; "slow" (env steps/s under half the median of the live
// workers); "silent" (no heartbeat for 3 s or more: about to time out); "waited on" (the
// synchronous iteration waits for its data and it is silent or slow).
struct WorkerView {
  int slot = -1;
  std::string host;
  uint64_t incarnation = 0;
  int envs = 0;
  double env_steps_per_s = 0;
  double heartbeat_age_s = 0;
  int64_t policy_version = -1;
  int64_t chunks_accepted = 0, chunks_rejected = 0;
  std::string status;
};
std::vector<WorkerView> DescribeWorkers(const std::vector<WorkerInfo>& live,
                                        WorkerRegistry::Clock::time_point now,
                                        const std::vector<int>& waiting_for_slots);

// Throughput counters read from /metrics' registry.
struct ThroughputView {
  int queue_depth = 0, queue_capacity = 0;
  std::vector<std::pair<std::string, double>> rejected;  // reason -> chunks
  std::vector<std::pair<std::string, double>> dropped;   // reason -> unrolls
  Metrics::HistogramValues policy_lag;
};
ThroughputView DescribeThroughput(const Metrics& metrics, int queue_capacity);

// Everything /api/status shows.
struct StatusView {
  bool live = true;
  std::string source;  // offline: the metrics file
  DashboardRunInfo run;
  RunState state;
  DashboardState::Snapshot snapshot;
  std::vector<WorkerView> workers;
  int needed_workers = 1;
  ThroughputView throughput;
};

// The live status of a learner. REQUIRES: all outlive the call.
StatusView LiveStatus(const DashboardState& state, const WorkerRegistry& registry,
                      const Metrics& metrics);

std::string StatusJson(const StatusView& view);
// `since`/`stride` as the client last saw them (0/0: everything).
std::string HistoryJson(const DashboardState::History& history);
std::string EvaluationsJson(const std::vector<InRunEvaluation>& evaluations);

// metrics.jsonl records.
std::string RunRecordJson(const DashboardRunInfo& info);
std::string WalkRecordJson(int64_t iteration, const std::vector<double>& edge_counts,
                           const WalkEventTotals& totals);

// A run's metrics.jsonl read back: iteration lines, "eval", "run" and "walk" records (later
// "run"/"walk" records replace earlier ones; unknown events are skipped). NOT_FOUND when the
// file cannot be read; INVALID_ARGUMENT naming the line for a line that is not JSON.
struct MetricsFile {
  std::optional<DashboardRunInfo> run;
  std::vector<IterationReport> iterations;
  std::vector<InRunEvaluation> evaluations;
  std::optional<int64_t> walk_iteration;
  std::vector<double> edge_counts;
  WalkEventTotals walk_totals;
  int skipped_lines = 0;  // blank or unknown records
};
absl::StatusOr<MetricsFile> ParseMetricsFile(const std::string& path);

// The status, history and evaluations of a recorded run, as the live API would give them
// (state "recorded"; no workers). `info` describes the run when the file has no "run" record
// (metrics files from before it): name and graph from the run's checkpoint.
struct RecordedDashboard {
  std::string status, history, evals;  // JSON documents
};
RecordedDashboard DashboardFromMetrics(const MetricsFile& file, const std::string& source,
                                       const std::optional<DashboardRunInfo>& info);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_JSON_H_
