// The rollout service across real processes on loopback: a learner and two workers; a worker
// killed with SIGKILL mid-unroll and restarted; the learner killed and resumed from its
// checkpoint with the workers rejoining by themselves; clean exits on SIGTERM.
#include <cstdlib>
#include <string>

#include "gmock/gmock.h"
#include "common/config_loader.h"
#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "learner/checkpoint.h"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

using testing::ChildProcess;
using testing::FreePort;
using testing::ScrapeMetric;
using testing::WaitFor;

class MultiProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir("juggle_mp_");
    port_ = FreePort();
    metrics_port_ = FreePort();
  }
  void TearDown() override {
    if (!HasFailure() && !std::getenv("JUGGLE_KEEP_TEST_LOGS")) std::system(("rm -rf " + dir_).c_str());
    else std::fprintf(stderr, "logs kept in %s\n", dir_.c_str());
  }
  // --resume_if_any, as the Kubernetes and Slurm templates start it: a new run the first time,
  // a resumed one after a restart.
  std::unique_ptr<ChildProcess> StartLearner() {
    std::vector<std::string> args = {"learner", "--config=tests/data/tiny_right_foot.textproto",
                                     "--port=" + std::to_string(port_),
                                     "--metrics_port=" + std::to_string(metrics_port_),
                                     "--run_dir=" + dir_ + "/run", "--resume_if_any"};
    return std::make_unique<ChildProcess>(args, dir_ + "/learner.log");
  }
  std::unique_ptr<ChildProcess> StartWorker(int slot) {
    return std::make_unique<ChildProcess>(
        std::vector<std::string>{"worker", "--learner=127.0.0.1:" + std::to_string(port_),
                                 "--envs=4", "--threads=1", "--slot=" + std::to_string(slot)},
        dir_ + "/worker" + std::to_string(slot) + ".log");
  }
  double Metric(const std::string& series) {
    return ScrapeMetric(metrics_port_, series).value_or(-1);
  }
  // Waits until the learner has trained `n` more iterations than now.
  bool TrainsFurther(int n, double seconds) {
    const double start = Metric("juggle_policy_version");
    return WaitFor([&] { return Metric("juggle_policy_version") >= start + n; }, seconds);
  }

  std::string dir_;
  int port_ = 0, metrics_port_ = 0;
};

TEST_F(MultiProcessTest, SurvivesWorkerAndLearnerDeathsAndResumes) {
  auto learner = StartLearner();
  auto w0 = StartWorker(0);
  auto w1 = StartWorker(1);
  ASSERT_TRUE(WaitFor([&] { return Metric("juggle_workers_connected") == 2; }, 60))
      << "workers did not register";
  ASSERT_TRUE(TrainsFurther(3, 60)) << "no training with two workers";
  EXPECT_GE(Metric("juggle_policy_broadcast_seconds_count"), 1)
      << "no version was measured reaching both workers";

  // A worker dies mid-unroll: training goes on with the other after its timeout.
  w1->Kill(SIGKILL);
  EXPECT_EQ(w1->Wait(5), -1);  // killed by a signal, not an exit
  ASSERT_TRUE(WaitFor([&] { return Metric("juggle_workers_connected") == 1; }, 20));
  EXPECT_GE(Metric("juggle_worker_timeouts_total"), 1);
  ASSERT_TRUE(TrainsFurther(3, 60)) << "training stopped after a worker died";

  // A restarted worker rejoins.
  w1 = StartWorker(1);
  ASSERT_TRUE(WaitFor([&] { return Metric("juggle_workers_connected") == 2; }, 60));
  ASSERT_TRUE(TrainsFurther(2, 60));
  EXPECT_LE(Metric("juggle_worker_reconnects_total{slot=\"1\"}"), 0)
      << "a new worker process is a restart, not a reconnect";

  // The learner dies; a resumed learner continues from its last checkpoint and the workers
  // rejoin by themselves.
  learner->Kill(SIGKILL);
  learner->Wait(5);
  absl::StatusOr<CheckpointDir::Loaded> last = CheckpointDir(dir_ + "/run/checkpoints").LoadLatest();
  ASSERT_TRUE(last.ok()) << last.status();
  learner = StartLearner();
  ASSERT_TRUE(WaitFor([&] { return Metric("juggle_workers_connected") == 2; }, 60))
      << "workers did not rejoin the resumed learner";
  const double resumed_at = Metric("juggle_policy_version");
  EXPECT_GE(Metric("juggle_worker_reconnects_total{slot=\"0\"}"), 1) << "counted as a reconnect";
  EXPECT_GE(Metric("juggle_worker_reconnects_total{slot=\"1\"}"), 1) << "counted as a reconnect";
  ASSERT_TRUE(TrainsFurther(2, 60));
  EXPECT_GE(resumed_at, 3);  // it did not start over from version 0
  const std::string log = ReadFile(dir_ + "/learner.log").value_or("");
  EXPECT_NE(log.find("no checkpoint in the run directory: starting a new run"), std::string::npos);
  EXPECT_NE(log.find("resuming from the run directory's newest checkpoint"), std::string::npos);

  // Clean exits on SIGTERM.
  w0->Kill(SIGTERM);
  w1->Kill(SIGTERM);
  EXPECT_EQ(w0->Wait(30), 0);
  EXPECT_EQ(w1->Wait(30), 0);
  learner->Kill(SIGTERM);
  EXPECT_EQ(learner->Wait(30), 0);
}

TEST_F(MultiProcessTest, LocalSynchronousModeIsDeterministicForAFixedSeed) {
  auto run = [&](const std::string& name) {
    ChildProcess train({"train", "--config=tests/data/tiny_right_foot.textproto",
                        "--iterations=3", "--workers=2", "--run_dir=" + dir_ + "/" + name},
                       dir_ + "/" + name + ".log");
    EXPECT_EQ(train.Wait(120), 0);
    absl::StatusOr<CheckpointDir::Loaded> ckpt = CheckpointDir(dir_ + "/" + name + "/checkpoints").LoadLatest();
    EXPECT_TRUE(ckpt.ok()) << ckpt.status();
    return ckpt.ok() ? ckpt->sections : Sections();
  };
  const Sections a = run("a"), b = run("b");
  ASSERT_TRUE(a.count("model") && b.count("model"));
  EXPECT_EQ(a.at("counters"), b.at("counters"));
  EXPECT_EQ(a.at("model"), b.at("model")) << "same seed and worker count, different parameters";
  EXPECT_EQ(a.at("edge_counts"), b.at("edge_counts"));
}

}  // namespace
}  // namespace juggle
