// Test helpers: a small right-foot config file naming the repository's graph and model by
// absolute paths, and a checkpoint of an untrained policy under it, written as the learner
// writes checkpoints (SaveLearnerState with the stored config). For tests of what checkpoints
// load after their config files change.
#ifndef JUGGLE_LEARNER_TESTING_UNTRAINED_CHECKPOINT_H_
#define JUGGLE_LEARNER_TESTING_UNTRAINED_CHECKPOINT_H_

#include <filesystem>
#include <fstream>
#include <string>

#include "common/adaptive_walk.h"
#include "envs/registry.h"
#include "envs/stored_config.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "learner/checkpoint.h"
#include "learner/learner_state.h"
#include "learner/ppo_trainer.h"

namespace juggle::testing {

// Writes a right-foot config with `seed` and a MoE of two `hidden`-unit layers to `path`.
inline void WriteSmallConfig(const std::string& path, int seed, int hidden) {
  std::ofstream(path) << "name: \"small\"\nseed: " << seed << "\n"
                      << "soccer_juggle {\n  graph_file: \""
                      << RepoPath("configs/graphs/right_foot.textproto")
                      << "\"\n  env { model_file: \"" << RepoPath("configs/models/juggle_scene.xml")
                      << "\" }\n}\nmodel { num_experts: 2 hidden: " << hidden
                      << " hidden: " << hidden << " gate_hidden: 16 gate_hidden: 16 }\n";
}

// Writes <run_dir>/checkpoints/ckpt-0000000001.jglc of an untrained policy under the config
// at `config_path` and returns its sections (empty, with a test failure, on error).
inline Sections WriteUntrainedCheckpoint(const std::string& config_path,
                                         const std::string& run_dir) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(config_path);
  EXPECT_TRUE(config.ok()) << config.status();
  if (!config.ok()) return {};
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  if (!spec.ok()) return {};
  PpoTrainer trainer(config->run.model(), config->run.ppo(), (*spec)->obs_dim(),
                     (*spec)->act_dim(), config->run.seed());
  AdaptiveWalk walk(config->graph.get());
  Sections sections =
      SaveLearnerState(StoreConfig(*config, **spec), config_path, trainer, walk, {});
  std::filesystem::create_directories(run_dir + "/checkpoints");
  const absl::Status written =
      WriteCheckpointFile(run_dir + "/checkpoints/ckpt-0000000001.jglc", sections);
  EXPECT_TRUE(written.ok()) << written;
  return sections;
}

}  // namespace juggle::testing

#endif  // JUGGLE_LEARNER_TESTING_UNTRAINED_CHECKPOINT_H_
