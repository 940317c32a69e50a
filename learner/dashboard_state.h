// What the learner's dashboard shows that /metrics cannot: a bounded history of iteration
// reports and in-run evaluations for the charts, the adaptive walk's counts and the workers'
// edge events per edge (cumulative and over the last iterations), the training loop's phase
// and the run's state (training / waiting for workers / stalled, with the reason).
//
// The training thread records into it; HTTP threads take snapshots. Memory is bounded: the
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
#include "learner/in_run_eval.h"
#include "learner/learner_metrics.h"

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

// Workers' edge events per edge (paper §5.2: chosen = the walk entered the edge's target,
// completed = the target node was completed, failed = the episode ended in it).
struct WalkEventTotals {
  std::vector<int64_t> chosen, completed, failed;  // [num_edges]
  void Resize(int num_edges);
  void Add(const EdgeEvent& event);
  void Add(const WalkEventTotals& other);
  int64_t events() const;
};

// What the training loop is doing.
enum class LoopPhase { kStarting, kWaitingForData, kUpdating, kEvaluating, kCheckpointing, kFinished };

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

class DashboardState {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kDefaultCapacity = 1000;     // history points
  static constexpr int kEvaluationCapacity = 200;   // evaluations kept
  static constexpr int kRecentIterations = 20;      // window of the "recent" edge events

  explicit DashboardState(DashboardRunInfo info, int capacity = kDefaultCapacity);

  const DashboardRunInfo& info() const { return info_; }

  // Training thread.
  void SetPhase(LoopPhase phase);
  // Synchronous mode: the live slots whose contribution of the current version is missing.
  void SetWaitingFor(std::vector<int> slots, int queue_depth);
  // One iteration: its report, the edge events it applied, the walk's counts after them.
  void RecordIteration(const IterationReport& report, const std::vector<EdgeEvent>& events,
                       const std::vector<double>& edge_counts, int64_t version);
  void RecordEvaluation(const InRunEvaluation& evaluation);
  void RecordCheckpoint();
  // The walk's counts and the policy version before the first iteration (after a resume).
  void SetInitial(const std::vector<double>& edge_counts, int64_t version,
                  int64_t total_samples, double train_seconds);

  // Any thread.
  struct History {
    std::vector<IterationReport> points;  // oldest first, every `stride`-th iteration
    std::vector<int64_t> sequences;       // each point's sequence number (1 = first recorded)
    int64_t stride = 1;
    int64_t last_sequence = 0;            // sequence number of the newest point (iterations recorded)
  };
  // Points with sequence > `since` when `stride` matches the current stride, else all of them.
  History HistorySince(int64_t since, int64_t stride) const;
  std::vector<InRunEvaluation> Evaluations() const;

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
    std::optional<IterationReport> latest;
    std::optional<InRunEvaluation> latest_evaluation;
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
  std::vector<std::pair<int64_t, IterationReport>> points_;  // (sequence, report)
  int64_t stride_ = 1;
  int64_t sequence_ = 0;
  std::optional<IterationReport> latest_;
  std::deque<double> recent_iteration_s_;
  std::vector<std::pair<int64_t, InRunEvaluation>> evaluations_;
  int64_t evaluation_stride_ = 1, evaluation_sequence_ = 0;
  std::optional<InRunEvaluation> latest_evaluation_;
  std::vector<double> edge_counts_;
  WalkEventTotals totals_;
  std::deque<WalkEventTotals> recent_;
  std::vector<int> waiting_for_;
  int queue_depth_ = 0;
};

// Short name of a loop phase ("waiting for data", ...).
const char* PhaseName(LoopPhase phase);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DASHBOARD_STATE_H_
