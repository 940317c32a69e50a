// Every run config in the repository loads (its base_config chain, graph and model files
// included) and makes its environment: a schema change cannot silently break a config that a
// doc tells readers to run. Control graphs are loaded through the run configs that name them;
// fuzzing inputs (tests/fuzz/corpus/) are not configs to keep valid. The toss in-loop configs
// name partner policies that `make train-toss` writes under runs/: for them the one error
// allowed is that file's absence (NOT_FOUND naming runs/), reached after every field before it.
#include <filesystem>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "envs/registry.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> RunConfigFiles(const fs::path& root) {
  std::vector<std::string> files;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    const std::string relative = fs::relative(it->path(), root).string();
    if (it->is_directory() &&
        (relative == "build" || relative == "configs/graphs" || relative == "tests/fuzz" ||
         absl::StartsWith(relative, "."))) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && it->path().extension() == ".textproto") files.push_back(relative);
  }
  return files;
}

TEST(AllConfigsTest, EveryRunConfigInTheRepositoryLoadsAndMakesItsEnvironment) {
  const char* root = std::getenv("JUGGLE_SOURCE_DIR");
  ASSERT_NE(root, nullptr) << "run through ctest (JUGGLE_SOURCE_DIR)";
  const std::vector<std::string> files = RunConfigFiles(root);
  int needs_training = 0;
  for (const std::string& file : files) {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(std::string(root) + "/" + file);
    if (!config.ok()) {
      const bool trained_partner_missing =
          config.status().code() == absl::StatusCode::kNotFound &&
          absl::StrContains(config.status().message(), "/runs/") &&
          absl::StrContains(config.status().message(), ".jglpolicy");
      if (trained_partner_missing) {
        ++needs_training;
      } else {
        ADD_FAILURE() << file << ": " << config.status();
      }
      continue;
    }
    EXPECT_FALSE(config->run.has_base_config()) << file << ": the loaded config keeps its base";
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
    EXPECT_TRUE(spec.ok()) << file << ": " << spec.status();
  }
  // The product configs, the experiment and ablation records and the test configs.
  EXPECT_GE(files.size(), 32u);
  EXPECT_LE(needs_training, 3);  // toss_loop1_catch, toss_loop1_throw, toss_loop2_catch
}

}  // namespace
}  // namespace juggle
