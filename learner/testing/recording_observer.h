// Test and benchmark helpers: TrainingObservers that keep every record they are told, in
// order, or call a function with each iteration record.
#ifndef JUGGLE_LEARNER_TESTING_RECORDING_OBSERVER_H_
#define JUGGLE_LEARNER_TESTING_RECORDING_OBSERVER_H_

#include <functional>
#include <vector>

#include "learner/training_observer.h"
#include "proto/run_log.pb.h"

namespace juggle {

class RecordingObserver : public TrainingObserver {
 public:
  std::vector<runlog::IterationRecord> iterations;
  std::vector<runlog::EvaluationRecord> evaluations;
  std::vector<runlog::CheckpointRecord> checkpoints;

  absl::Status OnIteration(const IterationEvent& event) override {
    iterations.push_back(event.record);
    return absl::OkStatus();
  }
  absl::Status OnEvaluation(const runlog::EvaluationRecord& record) override {
    evaluations.push_back(record);
    return absl::OkStatus();
  }
  absl::Status OnCheckpoint(const runlog::CheckpointRecord& record) override {
    checkpoints.push_back(record);
    return absl::OkStatus();
  }
};

// Calls `fn` with every iteration record (benchmarks that time iterations).
class IterationCallback : public TrainingObserver {
 public:
  explicit IterationCallback(std::function<void(const runlog::IterationRecord&)> fn)
      : fn_(std::move(fn)) {}
  absl::Status OnIteration(const IterationEvent& event) override {
    fn_(event.record);
    return absl::OkStatus();
  }

 private:
  std::function<void(const runlog::IterationRecord&)> fn_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_TESTING_RECORDING_OBSERVER_H_
