// The uniform-walk ablation switch (ServiceConfig.adaptive_walk): with it off, a short run's
// checkpointed edge counts are still the graph's base weights; with it on (the default), the
// same run moves them. Local learner + one in-process worker, tiny right-foot config.
#include <cstring>
#include <vector>

#include "common/adaptive_walk.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "gtest/gtest.h"
#include "learner/checkpoint.h"
#include "learner/learner_server.h"
#include "tests/one_worker_training.h"

namespace juggle {
namespace {

// Trains 3 iterations; returns the checkpoint's edge counts and the graph's base counts.
void TrainAndReadCounts(bool adaptive, std::vector<double>* counts, std::vector<double>* base) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig("tests/data/tiny_right_foot.textproto");
  ASSERT_TRUE(config.ok()) << config.status();
  config->run.mutable_service()->set_adaptive_walk(adaptive);
  config->run.mutable_evaluation()->set_every_minutes(0);
  *base = AdaptiveWalk(config->graph.get()).counts();
  const std::string dir = MakeTempDir("juggle_walk_");
  LearnerOptions o;
  o.config = *config;
  o.run_dir = dir;
  o.port = 0;
  o.listen_all_interfaces = false;
  o.max_iterations = 3;
  auto server = LearnerServer::Start(std::move(o));
  ASSERT_TRUE(server.ok()) << server.status();
  EXPECT_TRUE(TrainWithOneWorker(**server).ok());
  absl::StatusOr<CheckpointDir::Loaded> loaded = CheckpointDir(dir + "/checkpoints").LoadLatest();
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  const std::string& bytes = loaded->sections.at("edge_counts");
  counts->resize(bytes.size() / sizeof(double));
  std::memcpy(counts->data(), bytes.data(), bytes.size());
  std::system(("rm -rf " + dir).c_str());
}

TEST(WalkAblationTest, UniformWalkKeepsTheBaseWeightsWhileTheAdaptiveWalkMovesThem) {
  std::vector<double> uniform, adaptive, base;
  TrainAndReadCounts(false, &uniform, &base);
  ASSERT_FALSE(base.empty());
  EXPECT_EQ(uniform, base);
  TrainAndReadCounts(true, &adaptive, &base);
  EXPECT_NE(adaptive, base);
}

}  // namespace
}  // namespace juggle
