// envs/stored_config: a stored config loads the same env from any folder after the files it was
// read from are gone, and a stored text that still names a file is refused before it is read.
#include "envs/stored_config.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/testing/temp_dir.h"
#include "common/testing/working_dir.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// A config folder of its own: cfg.textproto naming graph.textproto and models/juggle_scene.xml
// by relative paths, as the shipped configs do.
std::string MakeConfigFolder() {
  const std::string dir = MakeTempDir("juggle_stored_config_");
  fs::copy(testing::RepoPath("configs/graphs/right_foot.textproto"), dir + "/graph.textproto");
  fs::create_directory(dir + "/models");
  for (const char* xml : {"juggle_scene.xml", "humanoid.xml", "ball.xml"}) {
    fs::copy(testing::RepoPath(std::string("configs/models/") + xml), dir + "/models/" + xml);
  }
  std::ofstream(dir + "/cfg.textproto")
      << "name: \"stored\"\nseed: 4242\n"
         "soccer_juggle { graph_file: \"graph.textproto\" "
         "env { model_file: \"models/juggle_scene.xml\" } }\n";
  return dir;
}

TEST(StoredConfigTest, LoadsTheSameEnvFromAnotherFolderAfterItsFilesAreDeleted) {
  const std::string dir = MakeConfigFolder();
  absl::StatusOr<LoadedConfig> original = LoadRunConfig(dir + "/cfg.textproto");
  ASSERT_TRUE(original.ok()) << original.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> original_spec = CreateEnvSpec(*original);
  ASSERT_TRUE(original_spec.ok()) << original_spec.status();
  // Offline demonstrations seed a fresh run only (proto/imitation.proto): not stored.
  original->run.mutable_imitation()->set_initial_demos_file("demos.jgld");
  const StoredConfig stored = StoreConfig(*original, **original_spec);
  fs::remove_all(dir);

  const std::string elsewhere = MakeTempDir("juggle_stored_config_elsewhere_");
  ScopedWorkingDir cd(elsewhere);
  absl::StatusOr<LoadedConfig> loaded =
      LoadStoredConfig(stored, "x.jglpolicy (stored)", dir + "/cfg.textproto");
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->run.seed(), 4242u);
  EXPECT_FALSE(loaded->run.imitation().has_initial_demos_file());
  EXPECT_EQ(loaded->config_path, dir + "/cfg.textproto");
  EXPECT_EQ(loaded->graph->num_nodes(), original->graph->num_nodes());
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*loaded);
  ASSERT_TRUE(spec.ok()) << spec.status();
  // The fingerprint covers the compiled model and the family's config section.
  EXPECT_EQ((*spec)->fingerprint(), (*original_spec)->fingerprint());
  fs::remove_all(elsewhere);
}

TEST(StoredConfigTest, RefusesATextThatNamesAFileBeforeReadingIt) {
  const StoredConfig stored{
      "soccer_juggle { graph_file: \"graphs/right_foot.textproto\" }\n", "mjb"};
  const absl::StatusOr<LoadedConfig> loaded = LoadStoredConfig(stored, "p (stored)", "c");
  EXPECT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            "p (stored): a stored config must have its files inlined, but it names one in "
            "soccer_juggle.graph_file");
  const StoredConfig based{"base_config: \"right_foot.textproto\"\n", "mjb"};
  EXPECT_THAT(LoadStoredConfig(based, "p (stored)", "c").status().message(),
              HasSubstr("names one in base_config"));
}

TEST(StoredConfigTest, RefusesAStoredConfigWithoutItsModel) {
  const absl::StatusOr<LoadedConfig> loaded =
      LoadStoredConfig({"seed: 1\n", ""}, "p (stored)", "c");
  EXPECT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(loaded.status().message(), HasSubstr("has no model"));
}

}  // namespace
}  // namespace juggle
