// Test helpers: shipped configs (paths relative to the repository root, where ctest runs),
// temporary config files, and "file:line:col" of text in a config under test.
#ifndef JUGGLE_ENVS_TESTING_TEST_CONFIGS_H_
#define JUGGLE_ENVS_TESTING_TEST_CONFIGS_H_

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "envs/mujoco_model.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/spec.h"
#include "envs/toss/spec.h"
#include "gtest/gtest.h"

namespace juggle::testing {

inline std::string RepoPath(const std::string& relative) {
  const char* root = std::getenv("JUGGLE_SOURCE_DIR");
  return root ? std::string(root) + "/" + relative : relative;
}

// The text of a repository file (empty when it cannot be read).
inline std::string ReadRepoFile(const std::string& relative) {
  std::ifstream in(RepoPath(relative));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Loads configs/<name>.textproto; fails the test on error.
inline absl::StatusOr<LoadedConfig> LoadShippedConfig(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(RepoPath("configs/" + name + ".textproto"));
  EXPECT_TRUE(config.ok()) << config.status();
  return config;
}

// Loads configs/<name>.textproto and builds its soccer-juggling spec; fails the test on error.
inline std::shared_ptr<const soccer_juggle::JuggleSpec> LoadSpec(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = LoadShippedConfig(name);
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const soccer_juggle::JuggleSpec>> spec =
      soccer_juggle::JuggleSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// Loads configs/<name>.textproto and builds its toss spec; fails the test on error.
inline std::shared_ptr<const toss::TossSpec> LoadTossSpec(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = LoadShippedConfig(name);
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const toss::TossSpec>> spec = toss::TossSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// Writes `text` to `name` in a directory of the running test's own (ctest runs tests of one
// fixture side by side, and they may write files of the same name); returns its path.
inline std::string WriteTemp(const std::string& name, const std::string& text) {
  std::string dir = ::testing::TempDir();
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  dir = test != nullptr ? absl::StrCat(dir, "/juggle_", test->test_suite_name(), ".", test->name())
                        : absl::StrCat(dir, "/juggle_pid", ::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = absl::StrCat(dir, "/", name);
  std::ofstream(path) << text;
  return path;
}

// configs/right_foot_planner.textproto on the control graph `graph_text` (written as
// graph.textproto in the test's temporary folder); `planner` goes inside its planner block.
inline absl::StatusOr<LoadedConfig> LoadRightFootPlannerWithGraph(const std::string& graph_text,
                                                                  const std::string& planner = "") {
  const std::string graph = WriteTemp("graph.textproto", graph_text);
  const std::string run = WriteTemp(
      "run.textproto",
      absl::StrCat("base_config: \"", RepoPath("configs/right_foot_planner.textproto"),
                   "\"\nname: \"t\"\nsoccer_juggle { graph_file: \"", graph, "\" }\n",
                   "planner { ", planner, " }\n"));
  return LoadRunConfig(run);
}

// The soccer spec of LoadRightFootPlannerWithGraph(graph_text); the error if it does not build.
inline absl::StatusOr<std::shared_ptr<const soccer_juggle::JuggleSpec>> SoccerSpecWithGraph(
    const std::string& graph_text) {
  absl::StatusOr<LoadedConfig> config = LoadRightFootPlannerWithGraph(graph_text);
  if (!config.ok()) return config.status();
  return soccer_juggle::JuggleSpec::Create(*config);
}

// configs/graphs/chest.textproto's chest_lean pose (inside `pose { chest_lean { ... } }`).
inline constexpr char kChestPose[] =
    "steady: true chest_amplitude: 0.7 neck_pitch: 0.6 knee: 0.2 ankle_amplitude: 0.2 dip: 0.3";

// A chest node's fields after its name and stage, as configs/graphs/chest.textproto's, with
// `pose` inside its chest_lean ("" for the release's lean).
inline std::string ChestNodeFields(const std::string& pose = kChestPose) {
  return absl::StrCat(" contact_body: \"chest\" contact_height: 1.41 apex_height: 2.0",
                      " ball_target { x: -0.09 y: 0 } pose { chest_lean { ", pose, " } }");
}

// "<file>:<line>:<column>" of the `occurrence`-th (0-based) appearance of `needle` in `text`,
// 1-based like the loader's messages. Fails the test if there is no such appearance.
inline std::string Loc(const std::string& file, const std::string& text, const std::string& needle,
                       int occurrence = 0) {
  size_t pos = std::string::npos;
  size_t from = 0;
  for (int i = 0; i <= occurrence; ++i) {
    pos = text.find(needle, from);
    if (pos == std::string::npos) {
      ADD_FAILURE() << "'" << needle << "' occurs fewer than " << occurrence + 1 << " times";
      return "<missing>";
    }
    from = pos + 1;
  }
  int line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < pos; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return absl::StrCat(file, ":", line, ":", pos - line_start + 1);
}

// Where the head's centre is (world) in `pose` of `spec`'s model, by forward kinematics.
inline std::array<double, 3> HeadCentre(const soccer_juggle::JuggleSpec& spec,
                                        const humanoid::CharacterPose& pose) {
  MjDataPtr data(mj_makeData(spec.model()));
  std::copy(pose.begin(), pose.end(), data->qpos);
  mj_kinematics(spec.model(), data.get());
  const double* p = data->geom_xpos + 3 * mj_name2id(spec.model(), mjOBJ_GEOM, "head");
  return {p[0], p[1], p[2]};
}

}  // namespace juggle::testing

#endif  // JUGGLE_ENVS_TESTING_TEST_CONFIGS_H_
