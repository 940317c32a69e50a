#include "learner/run_log.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "google/protobuf/util/json_util.h"

namespace juggle {
namespace {

using google::protobuf::util::JsonParseOptions;
using google::protobuf::util::JsonPrintOptions;
using google::protobuf::util::JsonStringToMessage;
using google::protobuf::util::MessageToJsonString;

constexpr char kEvalEvent[] = "eval";
constexpr char kRunEvent[] = "run";
constexpr char kCheckpointEvent[] = "walk";

// JSON errors of protobuf's own status type, as INVALID_ARGUMENT.
absl::Status Converted(const google::protobuf::util::Status& s) {
  return s.ok() ? absl::OkStatus() : absl::InvalidArgumentError(std::string(s.message()));
}

// Parses one line into `record`; a line with another or no event is left to the caller.
absl::Status ParseLine(const std::string& line, runlog::RunLogRecord* record, bool* known) {
  JsonParseOptions options;
  options.ignore_unknown_fields = true;
  runlog::RecordHeader header;
  absl::Status s = Converted(JsonStringToMessage(line, &header, options));
  if (!s.ok()) return s;
  *known = true;
  if (header.event().empty()) {
    return Converted(JsonStringToMessage(line, record->mutable_iteration(), options));
  } else if (header.event() == kEvalEvent) {
    return Converted(JsonStringToMessage(line, record->mutable_evaluation(), options));
  } else if (header.event() == kRunEvent) {
    return Converted(JsonStringToMessage(line, record->mutable_run(), options));
  } else if (header.event() == kCheckpointEvent) {
    return Converted(JsonStringToMessage(line, record->mutable_checkpoint(), options));
  }
  *known = false;
  return absl::OkStatus();
}

}  // namespace

std::string RunLogPath(const std::string& run_dir) { return run_dir + "/metrics.jsonl"; }

std::string RecordJson(const google::protobuf::Message& record) {
  JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string json;
  // Printing a generated message with no Any fields cannot fail.
  (void)MessageToJsonString(record, &json, options);
  return json;
}

absl::StatusOr<std::unique_ptr<RunLogWriter>> RunLogWriter::Open(const std::string& path,
                                                                 runlog::RunRecord run) {
  absl::StatusOr<std::unique_ptr<AppendFile>> file = AppendFile::Open(path);
  if (!file.ok()) return file.status();
  std::unique_ptr<RunLogWriter> writer(new RunLogWriter(*std::move(file)));
  run.set_event(kRunEvent);
  if (absl::Status s = writer->Write(run); !s.ok()) return s;
  return writer;
}

absl::Status RunLogWriter::Write(const google::protobuf::Message& record) {
  return file_->Append(absl::StrCat(RecordJson(record), "\n"));
}

absl::Status RunLogWriter::OnIteration(const IterationEvent& event) { return Write(event.record); }

absl::Status RunLogWriter::OnEvaluation(const runlog::EvaluationRecord& record) {
  if (record.event() == kEvalEvent) return Write(record);
  runlog::EvaluationRecord stamped = record;
  stamped.set_event(kEvalEvent);
  return Write(stamped);
}

absl::Status RunLogWriter::OnCheckpoint(const runlog::CheckpointRecord& record) {
  if (record.event() == kCheckpointEvent) return Write(record);
  runlog::CheckpointRecord stamped = record;
  stamped.set_event(kCheckpointEvent);
  return Write(stamped);
}

const runlog::RunRecord* RunLog::LastRun() const {
  for (auto it = records.rbegin(); it != records.rend(); ++it) {
    if (it->has_run()) return &it->run();
  }
  return nullptr;
}

int RunLog::CountOf(runlog::RunLogRecord::RecordCase kind) const {
  int n = 0;
  for (const runlog::RunLogRecord& r : records) n += r.record_case() == kind;
  return n;
}

absl::StatusOr<RunLog> ReadRunLog(const std::string& path) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) {
    return absl::Status(text.status().code(),
                        absl::StrCat("cannot read the run log: ", text.status().message()));
  }
  const std::vector<absl::string_view> lines = absl::StrSplit(*text, '\n');
  RunLog log;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string line(lines[i]);
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      if (i + 1 < lines.size()) ++log.skipped_lines;  // not the end of the last line
      continue;
    }
    runlog::RunLogRecord record;
    bool known = false;
    if (absl::Status s = ParseLine(line, &record, &known); !s.ok()) {
      const bool last = i + 1 == lines.size() || (i + 2 == lines.size() && lines[i + 1].empty());
      if (last) {
        ++log.skipped_lines;  // a line still being written
        break;
      }
      return absl::InvalidArgumentError(
          absl::StrCat(path, ":", i + 1, ": not a run-log record: ", s.message()));
    }
    if (!known) {
      ++log.skipped_lines;
      continue;
    }
    log.records.push_back(std::move(record));
  }
  return log;
}

}  // namespace juggle
