// What the training loop tells the parts that report on it: the run log (run_log.h), the
// Prometheus metrics (learner_metrics.h), the dashboard's state (dashboard_state.h), the
// console line (console_reporter.h) — each a TrainingObserver, none known to the loop by name
// (the pattern of Reverb's table extensions). The events carry the run log's typed records
// (proto/run_log.proto), so a new quantity is a new field of a record and reaches the file,
// the dashboard's API and any observer that wants it without a new hook.
//
// Thread-safety: the training thread calls every hook, one at a time, in the order of the
// events; an observer shared with other threads (the dashboard's state) locks itself.
#ifndef JUGGLE_LEARNER_TRAINING_OBSERVER_H_
#define JUGGLE_LEARNER_TRAINING_OBSERVER_H_

#include <vector>

#include "absl/status/status.h"
#include "common/adaptive_walk.h"
#include "proto/run_log.pb.h"

namespace juggle {

// What the training loop is doing.
enum class LoopPhase { kStarting, kWaitingForData, kUpdating, kEvaluating, kCheckpointing, kFinished };

// Short name of a loop phase ("waiting for data", ...).
const char* PhaseName(LoopPhase phase);

// One PPO iteration.
struct IterationEvent {
  const runlog::IterationRecord& record;
  const WalkEventTotals& walk_events;       // the edge events the iteration applied, per edge
  const std::vector<double>& edge_counts;   // the walk's counts after them
};

// The loop's phase; while it waits for data in synchronous mode, also whom it waits for.
struct PhaseEvent {
  LoopPhase phase = LoopPhase::kStarting;
  std::vector<int> waiting_for_slots;       // live slots without data of the current version
  int queue_depth = 0;                      // chunks in the ingestion queue
};

class TrainingObserver {
 public:
  virtual ~TrainingObserver() = default;
  // An error stops training: the loop checkpoints and returns it (a run log that cannot be
  // written must not become a silent gap).
  virtual absl::Status OnIteration(const IterationEvent& event) { return absl::OkStatus(); }
  virtual absl::Status OnEvaluation(const runlog::EvaluationRecord& record) {
    return absl::OkStatus();
  }
  // After a checkpoint was written: its path and the walk's state then.
  virtual absl::Status OnCheckpoint(const runlog::CheckpointRecord& record) {
    return absl::OkStatus();
  }
  // Called on every pass of the loop; cheap observers only.
  virtual void OnPhase(const PhaseEvent& event) {}
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_TRAINING_OBSERVER_H_
