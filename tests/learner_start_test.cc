// The learner builds the env spec before it listens: a config that parses but cannot make an
// environment fails at start with the reason, in the library and on the command line — never a
// worker re-registering in silence.
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// Loads (the shared and family checks pass) but its sim_dt differs from the model's timestep,
// which only building the spec against the model reveals.
std::string WriteMismatchedConfig(const std::string& dir) {
  const std::string path = dir + "/mismatch.textproto";
  std::ofstream(path) << "name: \"mismatch\"\n"
                      << "soccer_juggle {\n"
                      << "  graph_file: \"" << std::getenv("JUGGLE_SOURCE_DIR")
                      << "/configs/graphs/right_foot.textproto\"\n"
                      << "  env { model_file: \"" << std::getenv("JUGGLE_SOURCE_DIR")
                      << "/configs/models/juggle_scene.xml\" sim_dt: 0.005 }\n"
                      << "}\n";
  return path;
}

TEST(LearnerStartTest, ConfigThatCannotMakeAnEnvFailsAtStartNamingTheField) {
  const std::string dir = MakeTempDir("juggle_learner_start_");
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(WriteMismatchedConfig(dir));
  ASSERT_TRUE(config.ok()) << config.status();  // it loads ...
  LearnerOptions options;
  options.config = *config;
  options.run_dir = dir + "/run";
  options.port = 0;
  options.listen_all_interfaces = false;
  absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(options);
  // ... but makes no environment, and the learner says why.
  ASSERT_EQ(server.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(server.status().message()), HasSubstr("does not make an environment"));
  EXPECT_THAT(std::string(server.status().message()), HasSubstr("mismatch.textproto:4"));
  EXPECT_THAT(std::string(server.status().message()),
              HasSubstr("sim_dt 0.005 differs from the model's timestep 0.0025"));
}

TEST(LearnerStartTest, TrainWithAConfigThatCannotMakeAnEnvExitsAtOnceWithTheReason) {
  const std::string dir = MakeTempDir("juggle_learner_start_");
  const std::string path = WriteMismatchedConfig(dir);
  const auto start = std::chrono::steady_clock::now();
  FILE* pipe = ::popen(absl::StrCat(JUGGLE_BINARY, " train --config=", path, " --run_dir=", dir,
                                    "/run --minutes=1 2>&1").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), pipe)) > 0) output.append(buf, n);
  const int status = ::pclose(pipe);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << output;
  EXPECT_THAT(output, HasSubstr("sim_dt 0.005 differs from the model's timestep"));
  EXPECT_THAT(output, ::testing::Not(HasSubstr("registered")));
  EXPECT_LT(seconds, 20) << "the run must not wait for --minutes";
}

}  // namespace
}  // namespace juggle
