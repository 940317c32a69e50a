// The console's view of training: one progress line per iteration (with the latest in-run
// evaluation at its end) and one line per evaluation, on stdout. A TrainingObserver that
// `juggle train` and `juggle learner` add; tests and benchmarks leave it out.
// Thread-compatible (the training thread).
#ifndef JUGGLE_LEARNER_CONSOLE_REPORTER_H_
#define JUGGLE_LEARNER_CONSOLE_REPORTER_H_

#include <string>

#include "learner/training_observer.h"
#include "proto/run_log.pb.h"

namespace juggle {

// "iter     3  samples      1200  ...  0.52s (wait 0.10, update 0.40)"; `latest_eval`, when not
// empty, is appended after " | ".
std::string ProgressLine(const runlog::IterationRecord& record, const std::string& latest_eval);

class ConsoleReporter : public TrainingObserver {
 public:
  absl::Status OnIteration(const IterationEvent& event) override;
  absl::Status OnEvaluation(const runlog::EvaluationRecord& record) override;

 private:
  std::string latest_eval_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_CONSOLE_REPORTER_H_
