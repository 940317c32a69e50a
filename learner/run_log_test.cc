// The run log: every record type written, read back and replayed into the dashboard's state
// (the same documents as the live learner's); files from before proto/run_log.proto; partial
// and malformed lines; a full disk and a read-only run directory.
#include "learner/run_log.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "absl/strings/str_split.h"
#include "common/file_io.h"
#include "common/testing/temp_dir.h"
#include "common/testing/unprivileged.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "learner/dashboard_json.h"
#include "learner/dashboard_report.h"
#include "learner/dashboard_state.h"
#include "learner/testing/two_node_run.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::testing::HasSubstr;
using Json = nlohmann::json;

runlog::IterationRecord Iteration(int i) {
  runlog::IterationRecord r;
  r.set_iteration(i);
  r.set_samples(100.0 * i);
  r.set_iteration_samples(100);
  r.set_train_s(0.5 * i);
  r.set_iteration_s(0.5);
  r.set_mean_return(0.25 * i);
  r.set_juggles_per_episode(1.5);
  r.set_policy_version(i);
  r.set_value_loss(0.125);
  (*r.mutable_outcomes())["ball_lost"] = 3;
  r.set_gate_specialization(0.5);
  r.set_gate_utilization(0.25);
  return r;
}

runlog::EvaluationRecord Evaluation(int iteration) {
  runlog::EvaluationRecord e;
  e.set_event("eval");
  e.set_iteration(iteration);
  e.set_samples(100.0 * iteration);
  e.set_episodes(3);
  e.set_median_juggles(4);
  e.set_p90_juggles(9);
  for (int j : {3, 4, 9}) e.add_juggles(j);
  (*e.mutable_outcomes())["ball_lost"] = 3;
  (*e.mutable_mean_metrics())["apex_error"] = 0.5;
  return e;
}

runlog::CheckpointRecord Checkpoint(int iteration) {
  runlog::CheckpointRecord c;
  c.set_event("walk");
  c.set_iteration(iteration);
  c.set_checkpoint("checkpoints/ckpt-0000000002.jglc");
  for (double w : {1.5, 2.0}) c.add_weights(w);
  for (double n : {2.0, 1.0}) c.add_chosen(n);
  for (double n : {1.0, 0.0}) c.add_completed(n);
  for (double n : {1.0, 4.0}) c.add_failed(n);
  return c;
}

// Writes a run, two iterations, an evaluation and a checkpoint to <dir>/metrics.jsonl, and
// tells `live` (when given) the same events, as the training loop would.
void WriteRun(const std::string& dir, DashboardState* live) {
  absl::StatusOr<std::unique_ptr<RunLogWriter>> writer =
      RunLogWriter::Open(RunLogPath(dir), RunRecordOf(TwoNodeRun(), 1700000000.5));
  ASSERT_TRUE(writer.ok()) << writer.status();
  WalkEventTotals none;
  none.Resize(2);
  const std::vector<double> counts = {1.0, 2.0};
  std::vector<TrainingObserver*> observers = {writer->get()};
  if (live != nullptr) observers.push_back(live);
  for (TrainingObserver* o : observers) {
    ASSERT_TRUE(o->OnIteration({Iteration(1), none, counts}).ok());
    ASSERT_TRUE(o->OnIteration({Iteration(2), none, counts}).ok());
    ASSERT_TRUE(o->OnEvaluation(Evaluation(2)).ok());
    ASSERT_TRUE(o->OnCheckpoint(Checkpoint(2)).ok());
  }
}

TEST(RunLogTest, EveryRecordTypeReadsBackAsWritten) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  WriteRun(dir, nullptr);
  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  ASSERT_EQ(log->records.size(), 5u);
  EXPECT_TRUE(MessageDifferencer::Equals(log->records[0].run(),
                                         RunRecordOf(TwoNodeRun(), 1700000000.5)));
  EXPECT_TRUE(MessageDifferencer::Equals(log->records[1].iteration(), Iteration(1)));
  EXPECT_TRUE(MessageDifferencer::Equals(log->records[2].iteration(), Iteration(2)));
  EXPECT_TRUE(MessageDifferencer::Equals(log->records[3].evaluation(), Evaluation(2)));
  EXPECT_TRUE(MessageDifferencer::Equals(log->records[4].checkpoint(), Checkpoint(2)));
  EXPECT_EQ(log->skipped_lines, 0);
  ASSERT_NE(log->LastRun(), nullptr);
  EXPECT_EQ(log->LastRun()->config(), "test_run");
}

TEST(RunLogTest, LinesKeepTheKeysScriptsRead) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  WriteRun(dir, nullptr);
  const std::string text = *ReadFile(RunLogPath(dir));
  const std::vector<std::string> lines = absl::StrSplit(text, '\n', absl::SkipEmpty());
  ASSERT_EQ(lines.size(), 5u);
  const Json iteration = Json::parse(lines[1]);
  EXPECT_FALSE(iteration.contains("event"));  // scripts tell iterations by its absence
  EXPECT_EQ(iteration["iteration"], 1);
  EXPECT_EQ(iteration["samples"], 100);       // a JSON number, not a string
  EXPECT_EQ(iteration["juggles_per_episode"], 1.5);
  EXPECT_EQ(iteration["outcomes"]["ball_lost"], 3);
  EXPECT_EQ(Json::parse(lines[3])["event"], "eval");
  EXPECT_EQ(Json::parse(lines[3])["median_juggles"], 4);
  EXPECT_EQ(Json::parse(lines[4])["event"], "walk");
  EXPECT_EQ(Json::parse(lines[0])["event"], "run");
}

TEST(RunLogTest, ANonFiniteLossIsWrittenAsValidJsonAndReadBack) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  auto writer = RunLogWriter::Open(RunLogPath(dir), RunRecordOf(TwoNodeRun(), 0));
  ASSERT_TRUE(writer.ok());
  runlog::IterationRecord diverged = Iteration(1);
  diverged.set_value_loss(std::nan(""));
  WalkEventTotals none;
  ASSERT_TRUE((*writer)->OnIteration({diverged, none, {}}).ok());
  const std::string text = *ReadFile(RunLogPath(dir));
  EXPECT_THAT(text, HasSubstr("\"value_loss\":\"NaN\""));
  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  EXPECT_TRUE(std::isnan(log->records[1].iteration().value_loss()));
}

TEST(RunLogTest, ReplayedIntoTheDashboardItGivesTheLiveDocuments) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  DashboardState live(TwoNodeRun());
  WriteRun(dir, &live);
  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  const std::unique_ptr<DashboardState> replayed = ReplayRunLog(*log, RunInfoOf(*log->LastRun()));
  EXPECT_EQ(HistoryJson(replayed->HistorySince(0, 0)), HistoryJson(live.HistorySince(0, 0)));
  EXPECT_EQ(EvaluationsJson(replayed->Evaluations()), EvaluationsJson(live.Evaluations()));
  const RecordedDashboard recorded = RecordedDashboardOf(*replayed, "metrics.jsonl", "2 iterations");
  const Json status = Json::parse(recorded.status);
  EXPECT_EQ(status["live"], false);
  EXPECT_EQ(status["state"]["state"], "recorded");
  EXPECT_EQ(status["run"]["config"], "test_run");
  EXPECT_EQ(status["progress"]["iteration"], 2);
  EXPECT_EQ(status["latest"]["gate_specialization"], 0.5);
  EXPECT_EQ(status["latest_eval"]["juggles"].size(), 3u);
  // The checkpoint record's walk: weights and per-node totals.
  EXPECT_EQ(status["graph"]["edges"][0]["weight"], 1.5);
  EXPECT_EQ(status["graph"]["nodes"][0]["failed"], 4);   // edge b->a ends in a
  EXPECT_EQ(status["graph"]["nodes"][1]["entered"], 2);  // edge a->b chosen twice
}

TEST(RunLogTest, ReadsFilesWrittenBeforeTheSchema) {
  // Lines as the learner wrote them before proto/run_log.proto (nlohmann, null for NaN).
  const std::string dir = MakeTempDir("juggle_run_log_");
  ASSERT_TRUE(WriteFile(RunLogPath(dir),
      "{\"event\":\"run\",\"config\":\"old\",\"config_path\":\"configs/x.textproto\","
      "\"family\":\"soccer_juggle\",\"seed\":3,\"mode\":\"synchronous\",\"min_workers\":1,"
      "\"max_policy_lag\":0,\"queue_capacity\":64,\"checkpoint_every\":50,"
      "\"worker_timeout_s\":10.0,\"control_dt\":0.0333,\"outcome_names\":[\"running\"],"
      "\"nodes\":[{\"name\":\"a\",\"stage\":\"DOWN\",\"initial\":true}],"
      "\"edges\":[{\"from\":0,\"to\":0,\"w0\":1.0}],\"started_unix\":1.5}\n"
      "{\"iteration\":1,\"samples\":3200,\"train_s\":1.5,\"samples_per_s\":2000.0,"
      "\"sim_s_per_s\":66.0,\"mean_return\":0.5,\"mean_episode_len\":80.0,"
      "\"completions_per_episode\":0.0,\"juggles_per_episode\":0.5,\"episodes\":40,"
      "\"policy_lag\":0.0,\"iteration_s\":1.5,\"wait_s\":0.5,\"update_s\":1.0,\"workers\":1,"
      "\"value_loss\":null,\"approx_kl\":0.01,\"actor_lr\":0.0001,\"policy_version\":1,"
      "\"queue_depth\":0,\"outcomes\":{\"ball_lost\":40}}\n"
      "{\"event\":\"eval\",\"iteration\":1,\"samples\":3200,\"train_s\":2.0,\"eval_s\":0.5,"
      "\"episodes\":2,\"median_juggles\":1.0,\"p10_juggles\":0.0,\"p90_juggles\":2.0,"
      "\"mean_juggles\":1.0,\"frac_juggles_ge_10\":0.0,\"frac_juggles_ge_20\":0.0,"
      "\"mean_return\":0.5,\"mean_episode_s\":3.0,\"outcomes\":{\"ball_lost\":2},"
      "\"juggles\":[0,2]}\n"
      "{\"event\":\"walk\",\"iteration\":1,\"weights\":[1.5],\"chosen\":[4],\"completed\":[1],"
      "\"failed\":[3]}\n").ok());
  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  ASSERT_EQ(log->records.size(), 4u);
  EXPECT_EQ(log->records[0].run().seed(), 3u);
  EXPECT_EQ(log->records[0].run().nodes(0).name(), "a");
  EXPECT_EQ(log->records[1].iteration().samples(), 3200);
  EXPECT_EQ(log->records[1].iteration().value_loss(), 0);  // null: unset
  EXPECT_FALSE(log->records[1].iteration().has_gate_specialization());
  EXPECT_EQ(log->records[1].iteration().outcomes().at("ball_lost"), 40);
  EXPECT_EQ(log->records[2].evaluation().juggles_size(), 2);
  EXPECT_EQ(log->records[3].checkpoint().failed(0), 3);
}

TEST(RunLogTest, APartialLastLineIsSkippedAndAMalformedOneEarlierIsNamed) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  const std::string line = RecordJson(Iteration(1));
  ASSERT_TRUE(WriteFile(RunLogPath(dir), line + "\n{\"event\":\"future\"}\n{\"iteration\": 3, \"sampl").ok());
  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  EXPECT_EQ(log->records.size(), 1u);
  EXPECT_EQ(log->skipped_lines, 2);  // the unknown event and the partial line

  ASSERT_TRUE(WriteFile(RunLogPath(dir), line + "\nnot json\n" + line + "\n").ok());
  log = ReadRunLog(RunLogPath(dir));
  EXPECT_EQ(log.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(log.status().message()), HasSubstr("metrics.jsonl:2: not a run-log record"));
  ASSERT_TRUE(WriteFile(RunLogPath(dir), "{\"iteration\": \"three\"}\n" + line + "\n").ok());
  EXPECT_THAT(std::string(ReadRunLog(RunLogPath(dir)).status().message()),
              HasSubstr("metrics.jsonl:1: not a run-log record"));
  EXPECT_EQ(ReadRunLog(dir + "/none.jsonl").status().code(), absl::StatusCode::kNotFound);
}

TEST(RunLogTest, AFullDiskIsAnErrorNamingTheFile) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  ASSERT_EQ(::symlink("/dev/full", RunLogPath(dir).c_str()), 0);
  absl::StatusOr<std::unique_ptr<RunLogWriter>> writer =
      RunLogWriter::Open(RunLogPath(dir), RunRecordOf(TwoNodeRun(), 0));
  EXPECT_EQ(writer.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(writer.status().message(),
            "cannot write " + dir + "/metrics.jsonl: No space left on device");
}

TEST(RunLogTest, AReadOnlyRunDirectoryIsAnErrorNamingTheFile) {
  const std::string dir = MakeTempDir("juggle_run_log_");
  ASSERT_EQ(::chmod(dir.c_str(), 0555), 0);
  EXPECT_EXIT(
      {
        DropRootPrivileges();  // root writes into read-only folders
        const absl::Status s =
            RunLogWriter::Open(RunLogPath(dir), RunRecordOf(TwoNodeRun(), 0)).status();
        std::fprintf(stderr, "%s\n", s.ToString().c_str());
        std::exit(s.code() == absl::StatusCode::kPermissionDenied ? 0 : 1);
      },
      ::testing::ExitedWithCode(0),
      "PERMISSION_DENIED: cannot open for appending .*/metrics.jsonl: Permission denied");
}

}  // namespace
}  // namespace juggle
