// `juggle eval` as a user runs it: the zero-action baseline's key=value line, and --record
// writing every episode one after another as a replayable trajectory.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "common/testing/temp_dir.h"
#include "common/testing/working_dir.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"
#include "record/trajectory.h"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

// The JSON objects of a JSON-lines file's text.
std::vector<nlohmann::json> JsonLines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  }
  return lines;
}

TEST(EvalCliTest, ZeroActionBaselineRecordsEachEpisodeInTurn) {
  const std::string dir = MakeTempDir("juggle_eval_");
  testing::ChildProcess eval({"eval", "--zero-action", "--config=configs/right_foot.textproto",
                              "--episodes=3", "--record=" + dir + "/eval.traj"},
                             dir + "/eval.log");
  ASSERT_EQ(eval.Wait(60), 0);
  std::ifstream log(dir + "/eval.log");
  std::string line, last;
  while (std::getline(log, line)) last = line;
  EXPECT_THAT(last, ::testing::HasSubstr("policy=zero_action"));
  EXPECT_THAT(last, ::testing::HasSubstr(" episodes=3 "));
  EXPECT_THAT(last, ::testing::HasSubstr("median_juggles=0 "));
  EXPECT_THAT(last, ::testing::HasSubstr("mean_completions=1.000"));
  EXPECT_THAT(last, ::testing::HasSubstr("mean_episode_s=0.500"));

  absl::StatusOr<Trajectory> t = ReadTrajectory(dir + "/eval.traj");
  ASSERT_TRUE(t.ok()) << t.status();
  ASSERT_GT(t->num_samples(), 0);
  EXPECT_EQ(t->family, "soccer_juggle");
  EXPECT_EQ(t->episode(t->num_samples() - 1), 2);
  EXPECT_NEAR(t->duration(), 3 * 0.5, 1e-9);  // three 0.5 s episodes back to back
  for (int i = 1; i < t->num_samples(); ++i) EXPECT_GE(t->time[i], t->time[i - 1]);
  std::system(("rm -rf " + dir).c_str());
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A planning model whose choices the executed model judges differently more often than
// max_disagreement_share (0 here) is reported on the last line and warned about, once.
TEST(EvalCliTest, APlanningModelIsReportedAndItsDisagreementsWarnedAboutOnce) {
  const std::string dir = MakeTempDir("juggle_eval_");
  testing::ChildProcess eval(
      {"eval", "--controller=planner", "--config=configs/right_foot_planner.textproto",
       "--episodes=1", "--max_seconds=2",
       "--planner-set=threads: 1 samples: 4 iterations: 1 planning_model { timestep_factor: 8 "
       "max_disagreement_share: 0 }"},
      dir + "/eval.log");
  ASSERT_EQ(eval.Wait(120), 0);
  const std::string log = ReadAll(dir + "/eval.log");
  EXPECT_THAT(log, ::testing::HasSubstr(" model_checks="));
  EXPECT_THAT(log, ::testing::HasSubstr(" planner_exact_rollout_steps="));
  // 20 ms steps: the model loses kicks the executed one makes (5 of 27 re-plans, measured).
  EXPECT_THAT(log, ::testing::Not(::testing::HasSubstr("model_disagreements=0 ")));
  const size_t warning = log.find("warning: the planning model and the executed model judged");
  EXPECT_NE(warning, std::string::npos) << log;
  EXPECT_EQ(log.find("warning: the planning model", warning + 1), std::string::npos) << "once";
  std::system(("rm -rf " + dir).c_str());
}


TEST(EvalCliTest, PrintsTheNodeTableAndWritesItAsJsonLines) {
  const std::string dir = MakeTempDir("juggle_eval_");
  testing::ChildProcess eval({"eval", "--zero-action", "--config=configs/right_foot.textproto",
                              "--episodes=3", "--json=" + dir + "/eval.jsonl"},
                             dir + "/eval.log");
  ASSERT_EQ(eval.Wait(60), 0) << ReadAll(dir + "/eval.log");
  const std::string log = ReadAll(dir + "/eval.log");
  // Zero action completes the DOWN node every time and fails in the UP node.
  EXPECT_THAT(log, ::testing::ContainsRegex("right_foot_down +3 +3 +1.000"));
  EXPECT_THAT(log, ::testing::ContainsRegex("right_foot_up +3 +0 +0.000"));
  const std::string json = ReadAll(dir + "/eval.jsonl");
  const std::vector<nlohmann::json> lines = JsonLines(json);
  ASSERT_EQ(lines.size(), 8u);  // summary, two nodes, two edges, three episodes
  EXPECT_EQ(lines[0]["table"], "summary");
  EXPECT_EQ(lines[0]["episodes"], 3);
  EXPECT_EQ(lines[1], nlohmann::json::parse(
                          "{\"table\":\"node\",\"node\":\"right_foot_down\",\"visits\":3,"
                          "\"completions\":3,\"success_rate\":1,\"endings\":{}}"));
  EXPECT_EQ(lines[2]["node"], "right_foot_up");
  EXPECT_EQ(lines[2]["visits"], 3);
  EXPECT_EQ(lines[2]["completions"], 0);
  // The edges: every episode went down -> up and ended there.
  EXPECT_EQ(lines[3], nlohmann::json::parse(
                          "{\"table\":\"edge\",\"from\":\"right_foot_down\",\"to\":\"right_foot_up\","
                          "\"chosen\":3,\"completed\":0,\"failed\":3}"));
  EXPECT_EQ(lines[4]["table"], "edge");
  EXPECT_EQ(lines[4]["chosen"], 0);
  double mean_juggles = 0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(lines[5 + i]["table"], "episode");
    EXPECT_EQ(lines[5 + i]["episode"], i);
    EXPECT_GT(lines[5 + i]["seconds"].get<double>(), 0.0);
    EXPECT_NE(lines[5 + i]["outcome"], "running");
    mean_juggles += lines[5 + i]["juggles"].get<double>() / 3;
  }
  EXPECT_DOUBLE_EQ(lines[0]["mean_juggles"].get<double>(), mean_juggles);
  std::system(("rm -rf " + dir).c_str());
}

// The policy shipped in policies/ (docs/learning.md) still loads with its config and still
// juggles: on the first 10 held-out starts every episode gets its first juggle (p10 = 1),
// which the same base controller with zero action does not (p10 = 0).
TEST(EvalCliTest, ShippedRightFootPolicyGetsTheFirstJuggleOnEveryHeldOutStart) {
  const std::string dir = MakeTempDir("juggle_eval_");
  testing::ChildProcess eval(
      {"eval", "--policy=policies/right_foot/kick_fb_30min.jglpolicy", "--episodes=10"},
      dir + "/eval.log");
  ASSERT_EQ(eval.Wait(120), 0) << ReadAll(dir + "/eval.log");
  const std::string log = ReadAll(dir + "/eval.log");
  EXPECT_THAT(log, ::testing::HasSubstr(" median_juggles=1 p10_juggles=1 "));
  EXPECT_THAT(log, ::testing::ContainsRegex("mean_juggles=1\\.[0-9]+"));
  std::system(("rm -rf " + dir).c_str());
}

// The shipped policy is self-contained: from a folder without configs or models it evaluates
// the same, and its recording (which names the policy file) replays there too.
TEST(EvalCliTest, ShippedPolicyRunsAndReplaysFromAnotherFolder) {
  const std::string policy =
      std::filesystem::absolute("policies/right_foot/kick_fb_30min.jglpolicy").string();
  const std::string dir = MakeTempDir("juggle_eval_elsewhere_");
  ScopedWorkingDir cd(dir);
  testing::ChildProcess eval({"eval", "--policy=" + policy, "--episodes=2", "--record=e.traj"},
                             dir + "/eval.log");
  ASSERT_EQ(eval.Wait(120), 0) << ReadAll(dir + "/eval.log");
  EXPECT_THAT(ReadAll(dir + "/eval.log"), ::testing::Not(::testing::HasSubstr("note:")));
  absl::StatusOr<Trajectory> t = ReadTrajectory(dir + "/e.traj");
  ASSERT_TRUE(t.ok()) << t.status();
  EXPECT_EQ(t->config_path, policy);
  testing::ChildProcess replay({"replay", "--trajectory=e.traj", "--out=e.html"},
                               dir + "/replay.log");
  ASSERT_EQ(replay.Wait(60), 0) << ReadAll(dir + "/replay.log");
  std::system(("rm -rf " + dir).c_str());
}

TEST(EvalCliTest, ForceSweepReportsTheLargestPassingForcePerDirection) {
  const std::string dir = MakeTempDir("juggle_eval_");
  testing::ChildProcess eval({"eval", "--zero-action", "--config=configs/right_foot.textproto",
                              "--episodes=2", "--max_seconds=2", "--force-sweep",
                              "--force-step=2", "--force-max=2", "--min-median-juggles=0",
                              "--json=" + dir + "/sweep.jsonl"},
                             dir + "/sweep.log");
  ASSERT_EQ(eval.Wait(120), 0) << ReadAll(dir + "/sweep.log");
  std::ifstream log(dir + "/sweep.log");
  std::string line, last;
  while (std::getline(log, line)) last = line;
  // Every force passes a threshold of 0 juggles.
  for (const char* d : {"+x", "-x", "+y", "-y", "+z", "-z"}) {
    EXPECT_THAT(last, ::testing::HasSubstr(absl::StrCat(" max_force_", d, "=2")));
  }
  const std::string json = ReadAll(dir + "/sweep.jsonl");
  int rows = 0;
  for (size_t at = json.find("\"table\":\"force_sweep\""); at != std::string::npos;
       at = json.find("\"table\":\"force_sweep\"", at + 1)) {
    ++rows;
  }
  EXPECT_EQ(rows, 12);  // 6 directions × {0, 2} N
  int limits = 0;
  for (const nlohmann::json& line : JsonLines(json)) {
    if (line["table"] != "force_limit") continue;
    ++limits;
    EXPECT_EQ(line["max_force_n"], 2) << line;
  }
  EXPECT_EQ(limits, 6);
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace juggle
