// The run log, <run_dir>/metrics.jsonl: the records of proto/run_log.proto, one JSON object per
// line. RunLogWriter is the one writer (a TrainingObserver: it writes what the loop reports);
// ReadRunLog the one reader (the offline dashboard, tests). Python readers: scripts/analysis/.
#ifndef JUGGLE_LEARNER_RUN_LOG_H_
#define JUGGLE_LEARNER_RUN_LOG_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/file_io.h"
#include "google/protobuf/message.h"
#include "learner/training_observer.h"
#include "proto/run_log.pb.h"

namespace juggle {

// <run_dir>/metrics.jsonl.
std::string RunLogPath(const std::string& run_dir);

// One record as its line's JSON (no newline): proto field names as keys, every field printed.
std::string RecordJson(const google::protobuf::Message& record);

// Appends records to a run log. Every write is checked: a full disk, a revoked permission or a
// read-only folder is an error naming the file and the reason (common/file_io.h's codes), never
// a silent gap. Thread-compatible (the training thread).
class RunLogWriter : public TrainingObserver {
 public:
  // Opens `path` for appending (a resumed run continues its log) and writes `run` (its "event"
  // is set here).
  static absl::StatusOr<std::unique_ptr<RunLogWriter>> Open(const std::string& path,
                                                            runlog::RunRecord run);

  absl::Status OnIteration(const IterationEvent& event) override;
  absl::Status OnEvaluation(const runlog::EvaluationRecord& record) override;
  absl::Status OnCheckpoint(const runlog::CheckpointRecord& record) override;

 private:
  explicit RunLogWriter(std::unique_ptr<AppendFile> file) : file_(std::move(file)) {}
  absl::Status Write(const google::protobuf::Message& record);
  std::unique_ptr<AppendFile> file_;
};

// A run log read back: every record in file order.
struct RunLog {
  std::vector<runlog::RunLogRecord> records;
  int skipped_lines = 0;  // blank lines, records of unknown events, a partial last line
  // The last "run" record, if any (a resumed run has one per start).
  const runlog::RunRecord* LastRun() const;
  int CountOf(runlog::RunLogRecord::RecordCase kind) const;
};

// Reads `path`. Files written before proto/run_log.proto read the same (same keys; null numbers
// read as unset); unknown keys are ignored (a newer writer's fields). NOT_FOUND naming the file
// when it cannot be read; INVALID_ARGUMENT "path:line: ..." for a line that is not a record
// (a run still being written may end in a partial line: that one is skipped).
absl::StatusOr<RunLog> ReadRunLog(const std::string& path);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_RUN_LOG_H_
