// The run log in a real training run (learner + one worker over loopback): every record type
// lands in <run_dir>/metrics.jsonl and renders as the dashboard; a run log that cannot be
// written stops the learner with the reason; an observer's error stops training, which still
// checkpoints.
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "learner/checkpoint.h"
#include "learner/dashboard_report.h"
#include "learner/learner_server.h"
#include "learner/run_log.h"
#include "learner/testing/recording_observer.h"
#include "tests/one_worker_training.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

TEST(RunLogTrainingTest, ATrainedRunLogsEveryRecordTypeAndRendersAsTheDashboard) {
  const std::string dir = MakeTempDir("juggle_run_log_training_");
  auto server = LearnerServer::Start(TinyRunOptions(dir, 2, /*evaluate_every=*/1, /*episodes=*/2));
  ASSERT_TRUE(server.ok()) << server.status();
  ASSERT_TRUE(TrainWithOneWorker(**server).ok());
  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  EXPECT_EQ(log->CountOf(runlog::RunLogRecord::kRun), 1);
  EXPECT_EQ(log->CountOf(runlog::RunLogRecord::kIteration), 2);
  EXPECT_EQ(log->CountOf(runlog::RunLogRecord::kEvaluation), 2);
  EXPECT_GE(log->CountOf(runlog::RunLogRecord::kCheckpoint), 2);  // every iteration + the end
  EXPECT_EQ(log->LastRun()->config(), "tiny_right_foot");
  EXPECT_EQ(log->records[1].iteration().iteration(), 1);
  absl::StatusOr<DashboardReport> report = RenderRunDashboard(dir);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_EQ(report->iterations, 2);
  EXPECT_EQ(report->evaluations, 2);
  EXPECT_TRUE(report->notes.empty());
  std::system(("rm -rf " + dir).c_str());
}

TEST(RunLogTrainingTest, ALearnerWhoseRunLogIsOnAFullDiskDoesNotStart) {
  const std::string dir = MakeTempDir("juggle_run_log_training_");
  ASSERT_EQ(::symlink("/dev/full", RunLogPath(dir).c_str()), 0);
  auto server = LearnerServer::Start(TinyRunOptions(dir, 1, 0));
  ASSERT_EQ(server.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(server.status().message(),
            "cannot write " + dir + "/metrics.jsonl: No space left on device");
  std::system(("rm -rf " + dir).c_str());
}

// Fails at its second iteration, as a run log on a disk that fills up would.
class FailsAtIterationTwo : public TrainingObserver {
 public:
  absl::Status OnIteration(const IterationEvent& event) override {
    ++seen;
    if (event.record.iteration() < 2) return absl::OkStatus();
    return absl::ResourceExhaustedError("cannot write metrics.jsonl: No space left on device");
  }
  int seen = 0;
};

TEST(RunLogTrainingTest, AnObserversErrorStopsTrainingWhichStillCheckpoints) {
  const std::string dir = MakeTempDir("juggle_run_log_training_");
  LearnerOptions o = TinyRunOptions(dir, 5, 0);
  FailsAtIterationTwo failing;
  o.observers.push_back(&failing);
  auto server = LearnerServer::Start(std::move(o));
  ASSERT_TRUE(server.ok()) << server.status();
  const absl::Status trained = TrainWithOneWorker(**server);
  EXPECT_EQ(trained.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(trained.message()), HasSubstr("No space left on device"));
  EXPECT_EQ(failing.seen, 2);  // no third iteration
  absl::StatusOr<CheckpointDir::Loaded> last = CheckpointDir(dir + "/checkpoints").LoadLatest();
  ASSERT_TRUE(last.ok()) << last.status();
  EXPECT_THAT(last->path, HasSubstr("ckpt-0000000002"));
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace juggle
