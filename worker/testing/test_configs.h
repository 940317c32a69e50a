// Test helpers: load shipped configs (paths relative to the repository root, where ctest runs).
#ifndef JUGGLE_WORKER_TESTING_TEST_CONFIGS_H_
#define JUGGLE_WORKER_TESTING_TEST_CONFIGS_H_

#include <cstdlib>
#include <memory>
#include <string>

#include "common/config_loader.h"
#include "gtest/gtest.h"
#include "worker/juggle_spec.h"

namespace juggle::testing {

inline std::string RepoPath(const std::string& relative) {
  const char* root = std::getenv("JUGGLE_SOURCE_DIR");
  return root ? std::string(root) + "/" + relative : relative;
}

// Loads configs/<name>.textproto and builds its spec; fails the test on error.
inline std::shared_ptr<const JuggleSpec> LoadSpec(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(RepoPath("configs/" + name + ".textproto"));
  EXPECT_TRUE(config.ok()) << config.status();
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = JuggleSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

}  // namespace juggle::testing

#endif  // JUGGLE_WORKER_TESTING_TEST_CONFIGS_H_
