// The dashboard's JSON documents (docs/dashboard.md has the schema), built with nlohmann/json:
//   /api/status   the run, its state, progress, throughput, workers, the control graph with the
//                 walk's weights and per-edge/per-node success, the latest evaluation;
//   /api/history  the iteration reports (bounded, thinned over the whole run);
//   /api/evals    the in-run evaluations.
// The live learner builds them from DashboardState, WorkerRegistry and Metrics; `juggle
// dashboard` from a DashboardState its run log was replayed into (dashboard_report.h), so one
// page renders both. Iteration and evaluation entries are the run log's records
// (proto/run_log.proto). Pure functions; thread-safe.
#ifndef JUGGLE_LEARNER_DASHBOARD_JSON_H_
#define JUGGLE_LEARNER_DASHBOARD_JSON_H_

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
  int64_t sessions = 1;  // the worker's registrations so far (more than 1: it reconnected)
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
  double reconnects = 0;  // juggle_worker_reconnects_total over every slot
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
std::string EvaluationsJson(const std::vector<runlog::EvaluationRecord>& evaluations);

// The documents of a recorded run: `state` holds its replayed run log; `summary` ends the
// state's reason ("rendered from <source> (<summary>)"). No workers, no ages.
struct RecordedDashboard {
  std::string status, history, evals;  // JSON documents
};
RecordedDashboard RecordedDashboardOf(const DashboardState& state, const std::string& source,
                                      const std::string& summary);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_JSON_H_
