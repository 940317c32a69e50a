// The learner builds the env spec before it listens: a config that parses but cannot make an
// environment fails at start with the reason, in the library and on the command line — never a
// worker re-registering in silence.
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "common/http_server.h"
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

// The HTTP port (/metrics, the dashboard) from LearnerOptions::metrics_port and the config's
// service.metrics_port, as both document: -1 defers to the config, 0 is off in either, a
// number is that port, kAnyFreePort a free one.
TEST(LearnerStartTest, MetricsPortZeroIsOffAndANumberIsThatPort) {
  const std::string dir = MakeTempDir("juggle_learner_start_");
  absl::StatusOr<LoadedConfig> config = LoadRunConfig("tests/data/tiny_right_foot.textproto");
  ASSERT_TRUE(config.ok()) << config.status();
  int run = 0;
  auto start = [&](const LoadedConfig& c, int metrics_port) {
    LearnerOptions options;
    options.config = c;
    options.run_dir = absl::StrCat(dir, "/run", run++);
    options.port = 0;
    options.metrics_port = metrics_port;
    options.listen_all_interfaces = false;
    absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(options);
    EXPECT_TRUE(server.ok()) << server.status();
    return server.ok() ? std::move(*server) : nullptr;
  };
  // The config leaves it unset (0): off, whether the options defer (-1) or say 0.
  for (int port : {-1, 0}) {
    std::unique_ptr<LearnerServer> server = start(*config, port);
    ASSERT_NE(server, nullptr);
    EXPECT_EQ(server->metrics_port(), 0) << "options.metrics_port " << port;
    server->Shutdown();
  }
  std::unique_ptr<LearnerServer> any = start(*config, LearnerOptions::kAnyFreePort);
  ASSERT_NE(any, nullptr);
  const int free_port = any->metrics_port();
  ASSERT_GT(free_port, 0);
  absl::StatusOr<std::string> health = HttpGet(free_port, "/healthz");
  ASSERT_TRUE(health.ok()) << health.status();
  EXPECT_EQ(*health, "ok\n");
  any->Shutdown();
  // The config names a port: -1 takes it, 0 still turns it off.
  LoadedConfig with_port = *config;
  with_port.run.mutable_service()->set_metrics_port(free_port);
  std::unique_ptr<LearnerServer> from_config = start(with_port, -1);
  ASSERT_NE(from_config, nullptr);
  EXPECT_EQ(from_config->metrics_port(), free_port);
  EXPECT_TRUE(HttpGet(free_port, "/healthz").ok());
  from_config->Shutdown();
  std::unique_ptr<LearnerServer> off = start(with_port, 0);
  ASSERT_NE(off, nullptr);
  EXPECT_EQ(off->metrics_port(), 0);
  EXPECT_EQ(HttpGet(free_port, "/healthz").status().code(), absl::StatusCode::kUnavailable);
  off->Shutdown();
  std::system(("rm -rf " + dir).c_str());
}

// Runs `juggle <args>` to the end; returns its exit code and output (stdout and stderr).
std::pair<int, std::string> RunJuggle(const std::string& args) {
  FILE* pipe = ::popen(absl::StrCat(JUGGLE_BINARY, " ", args, " 2>&1").c_str(), "r");
  std::string output;
  char buf[4096];
  size_t n;
  while (pipe != nullptr && (n = std::fread(buf, 1, sizeof(buf), pipe)) > 0) output.append(buf, n);
  const int status = pipe == nullptr ? -1 : ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

TEST(LearnerStartTest, LocalTrainingServesTheDashboardOnAFreePortUnlessTurnedOff) {
  const std::string dir = MakeTempDir("juggle_learner_start_");
  const std::string common =
      " --config=tests/data/tiny_right_foot.textproto --iterations=1 --workers=1";
  auto [code, output] = RunJuggle("train" + common + " --run_dir=" + dir + "/on");
  EXPECT_EQ(code, 0) << output;
  EXPECT_THAT(output, ::testing::ContainsRegex("dashboard: http://127\\.0\\.0\\.1:[0-9]+/"));
  auto [off_code, off_output] =
      RunJuggle("train" + common + " --metrics_port=0 --run_dir=" + dir + "/off");
  EXPECT_EQ(off_code, 0) << off_output;
  EXPECT_THAT(off_output, ::testing::Not(HasSubstr("dashboard:")));
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace juggle
