// Checkpoints of a training run, as its observers are told: one per checkpoint iteration and a
// final one when the run stops, never the same iteration twice. Local learner + one in-process
// worker, tiny right-foot config.
#include <cstdlib>
#include <vector>

#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"
#include "learner/testing/recording_observer.h"
#include "tests/one_worker_training.h"

namespace juggle {
namespace {

// The iterations of the checkpoint records of a run of `iterations` with `every`.
std::vector<int> CheckpointIterations(int iterations, int every) {
  const std::string dir = MakeTempDir("juggle_ckpt_records_");
  LearnerOptions o = TinyRunOptions(dir, iterations, /*evaluate_every=*/0);
  o.config.run.mutable_service()->set_checkpoint_every(every);
  RecordingObserver recorded;
  o.observers.push_back(&recorded);
  auto server = LearnerServer::Start(std::move(o));
  EXPECT_TRUE(server.ok()) << server.status();
  if (!server.ok()) return {};
  EXPECT_TRUE(TrainWithOneWorker(**server).ok());
  std::system(("rm -rf " + dir).c_str());
  std::vector<int> out;
  for (const runlog::CheckpointRecord& r : recorded.checkpoints) out.push_back(r.iteration());
  return out;
}

TEST(CheckpointRecordsTest, ARunEndingOnACheckpointIterationRecordsItOnce) {
  EXPECT_EQ(CheckpointIterations(/*iterations=*/4, /*every=*/2), (std::vector<int>{2, 4}));
}

TEST(CheckpointRecordsTest, ARunEndingBetweenCheckpointsRecordsItsLastIteration) {
  EXPECT_EQ(CheckpointIterations(/*iterations=*/3, /*every=*/2), (std::vector<int>{2, 3}));
}

}  // namespace
}  // namespace juggle
