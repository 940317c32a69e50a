// What the learner's dashboard shows that /metrics cannot: a bounded history of iteration
// records and in-run evaluations for the charts, the adaptive walk's counts and the workers'
// edge events per edge (cumulative and over the last iterations), the training loop's phase
// and the run's state (training / waiting for workers / stalled, with the reason).
//
// Live, the training loop tells it what happens (a TrainingObserver); offline, `juggle
// dashboard` replays a run log into it (dashboard_report.h) — one state, one page. HTTP threads
// take snapshots. Memory is bounded: the
// history keeps at most `capacity` points spread over the whole run (when full, every second
// point goes and the stride doubles), evaluations likewise, the recent edge events a fixed
// window. Thread-safe (one mutex; recording is a few copies per iteration).
#ifndef JUGGLE_LEARNER_DASHBOARD_STATE_H_
#define JUGGLE_LEARNER_DASHBOARD_STATE_H_

#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/adaptive_walk.h"
#include "common/config_loader.h"
#include "common/control_graph.h"
#include "envs/env.h"
#include "learner/training_observer.h"
#include "proto/run_log.pb.h"

namespace juggle {

// The run as configured: fixed for the learner's life.
struct DashboardRunInfo {
  std::string config_name;
  std::string config_path;
  std::string family;
  uint64_t seed = 0;
  bool synchronous = true;
  int min_workers = 1;
  int max_policy_lag = 0;
  int queue_capacity = 0;
  int checkpoint_every = 0;
  double worker_timeout_s = 10;
  double control_dt = 0;
  std::vector<std::string> outcome_names;
  struct Node {
    std::string name;
    std::string stage;  // "DOWN", "UP", "STALL"
    bool initial = false;
  };
  struct Edge {
    int from = -1, to = -1;
    double base_weight = 1;
  };
  std::vector<Node> nodes;
  std::vector<Edge> edges;
};

// The graph part of a DashboardRunInfo from a control graph (empty graph: no nodes).
void DescribeGraph(const ControlGraph& graph, DashboardRunInfo* info);
// The whole DashboardRunInfo of a loaded config and its env spec.
DashboardRunInfo DescribeRun(const LoadedConfig& config, const EnvSpec& spec);
// The run log's "run" record of a run, and back (started_unix: when the learner started).
runlog::RunRecord RunRecordOf(const DashboardRunInfo& info, double started_unix);
DashboardRunInfo RunInfoOf(const runlog::RunRecord& record);

// The run's state as shown: `state` is one of "starting", "training", "waiting for workers",
// "stalled", "evaluating", "checkpointing", "finished"; `reason` says why when it is not
// plainly training.
struct RunState {
  std::string state;
  std::string reason;
};

// Inputs of the state decision, and the decision itself (a pure function, unit-tested).
struct RunStateInputs {
  LoopPhase phase = LoopPhase::kStarting;
  double phase_seconds = 0;             // in the current phase
  int live_workers = 0;
  int needed_workers = 1;               // synchronous: min_workers; asynchronous: 1
  bool synchronous = true;
  double seconds_since_progress = 0;    // since the last iteration (or since training began)
  double typical_iteration_s = 0;       // median of the recent iterations (0: none yet)
  int64_t version = 0;
  std::vector<int> waiting_for_slots;   // synchronous: live slots without data of `version`
  int queue_depth = 0, queue_capacity = 0;
};
// Stalled: no iteration for longer than max(kStallFloorSeconds, 10 × the typical iteration).
constexpr double kStallFloorSeconds = 60;
RunState DecideRunState(const RunStateInputs& in);

class DashboardState : public TrainingObserver {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kDefaultCapacity = 1000;     // history points
  static constexpr int kEvaluationCapacity = 200;   // evaluations kept
  static constexpr int kRecentIterations = 20;      // window of the "recent" edge events

  explicit DashboardState(DashboardRunInfo info, int capacity = kDefaultCapacity);

  const DashboardRunInfo& info() const { return info_; }

  // The training loop's events (training thread) or a run log's records (a replay).
  absl::Status OnIteration(const IterationEvent& event) override;
  absl::Status OnEvaluation(const runlog::EvaluationRecord& record) override;
  // Also takes the record's walk weights and event totals (when they match the graph).
  absl::Status OnCheckpoint(const runlog::CheckpointRecord& record) override;
  // The phase; while waiting for data, the slots waited for and the queue's depth.
  void OnPhase(const PhaseEvent& event) override;
  // The walk's counts and the policy version before the first iteration (after a resume).
  void SetInitial(const std::vector<double>& edge_counts, int64_t version,
                  int64_t total_samples, double train_seconds);

  // Any thread.
  struct History {
    std::vector<runlog::IterationRecord> points;  // oldest first, every `stride`-th iteration
    std::vector<int64_t> sequences;       // each point's sequence number (1 = first recorded)
    int64_t stride = 1;
    int64_t last_sequence = 0;            // sequence number of the newest point (iterations recorded)
  };
  // Points with sequence > `since` when `stride` matches the current stride, else all of them.
  History HistorySince(int64_t since, int64_t stride) const;
  std::vector<runlog::EvaluationRecord> Evaluations() const;

  struct Snapshot {
    LoopPhase phase = LoopPhase::kStarting;
    double phase_seconds = 0;
    double uptime_s = 0;
    std::optional<double> checkpoint_age_s;   // none: no checkpoint written by this process
    std::optional<double> iteration_age_s;    // none: no iteration yet
    double seconds_since_progress = 0;        // since the last iteration, or training's start
    double typical_iteration_s = 0;
    int64_t version = 0;
    int64_t total_samples = 0;
    double train_seconds = 0;
    std::optional<runlog::IterationRecord> latest;
    std::optional<runlog::EvaluationRecord> latest_evaluation;
    std::vector<double> edge_counts;
    WalkEventTotals totals;   // since the learner started
    WalkEventTotals recent;   // over the last kRecentIterations iterations
    std::vector<int> waiting_for_slots;
    int queue_depth = 0;
  };
  Snapshot Take() const;

 private:
  const DashboardRunInfo info_;
  const int capacity_;
  const Clock::time_point start_;
  mutable std::mutex mu_;
  LoopPhase phase_ = LoopPhase::kStarting;
  Clock::time_point phase_since_;
  std::optional<Clock::time_point> last_checkpoint_, last_iteration_;
  Clock::time_point last_progress_;  // the last iteration, or when training began
  int64_t version_ = 0, total_samples_ = 0;
  double train_seconds_ = 0;
  std::vector<std::pair<int64_t, runlog::IterationRecord>> points_;  // (sequence, record)
  int64_t stride_ = 1;
  int64_t sequence_ = 0;
  std::optional<runlog::IterationRecord> latest_;
  std::deque<double> recent_iteration_s_;
  std::vector<std::pair<int64_t, runlog::EvaluationRecord>> evaluations_;
  int64_t evaluation_stride_ = 1, evaluation_sequence_ = 0;
  std::optional<runlog::EvaluationRecord> latest_evaluation_;
  std::vector<double> edge_counts_;
  WalkEventTotals totals_;
  std::deque<WalkEventTotals> recent_;
  std::vector<int> waiting_for_;
  int queue_depth_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_STATE_H_
