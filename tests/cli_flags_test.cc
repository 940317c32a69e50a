// The command line as a user meets it: typed flags that name the wrong one and exit 2 (never
// abort), help for every command, unknown commands and flags.
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

struct Result {
  int exit_code = -1;  // -1: killed by a signal (an abort)
  std::string output;  // stdout and stderr
};

Result RunBinary(const std::string& binary, const std::string& args) {
  Result r;
  FILE* pipe = ::popen((binary + " " + args + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), pipe)) > 0) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

Result Juggle(const std::string& args) { return RunBinary(JUGGLE_BINARY, args); }

TEST(CliFlagsTest, MalformedNumberNamesTheFlagAndExitsTwo) {
  const Result r = Juggle("train --iterations=abc");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--iterations"));
  EXPECT_THAT(r.output, HasSubstr("abc"));
  EXPECT_THAT(r.output, HasSubstr("juggle train --help"));
}

TEST(CliFlagsTest, OutOfRangeNumberNamesTheFlagAndTheRangeAndExitsTwo) {
  const Result r = Juggle("train --envs=-1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--envs"));
  EXPECT_THAT(r.output, HasSubstr("must lie in [0, 100000], got -1"));
}

TEST(CliFlagsTest, EveryCommandsBadNumbersExitTwoWithoutAborting) {
  for (const char* args : {"eval --episodes=x", "worker --envs=0", "render --width=abc",
                           "simulate --seconds=-3", "toss --seeds=0", "bench sim --envs=nope",
                           "learner --port=70000", "eval --max_seconds=nan"}) {
    SCOPED_TRACE(args);
    const Result r = Juggle(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr("error: "));
  }
}

TEST(CliFlagsTest, ThePlannersOwnEvalOutputsWithoutThePlannerAreUsageErrors) {
  for (const char* flag : {"--rescue-samples-out=/tmp/never_written.jsonl",
                           "--kick-memory-out=/tmp/never_written.txt"}) {
    SCOPED_TRACE(flag);
    const Result r = Juggle(std::string("eval --zero-action ") + flag);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr("needs --controller=planner"));
  }
}

TEST(CliFlagsTest, UnknownFlagAndUnknownCommandAreUsageErrors) {
  const Result flag = Juggle("eval --no_such_flag=1");
  EXPECT_EQ(flag.exit_code, 2) << flag.output;
  EXPECT_THAT(flag.output, HasSubstr("--no_such_flag"));
  const Result command = Juggle("juggle-harder");
  EXPECT_EQ(command.exit_code, 2) << command.output;
  EXPECT_THAT(command.output, HasSubstr("juggle-harder"));
}

TEST(CliFlagsTest, TopLevelHelpListsEveryCommand) {
  const Result r = Juggle("--help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* command : {"train", "learner", "worker", "eval", "simulate", "check-config",
                              "render", "siteswap", "toss", "export-policy", "bench",
                              "dashboard"}) {
    EXPECT_THAT(r.output, HasSubstr(command));
  }
}

TEST(CliFlagsTest, CommandHelpListsItsFlagsWithDefaults) {
  const Result r = Juggle("train --help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* flag : {"--config", "--run_dir", "--resume", "--init_from", "--iterations",
                           "--minutes", "--workers", "--envs", "--threads", "--metrics_port"}) {
    EXPECT_THAT(r.output, HasSubstr(flag));
  }
  EXPECT_THAT(r.output, HasSubstr("configs/right_foot.textproto"));
}

TEST(CliFlagsTest, DashboardNeedsARunDirWithAMetricsFile) {
  const Result missing = Juggle("dashboard");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("--run_dir"));
  const Result empty = Juggle("dashboard --run_dir=/nonexistent/run");
  EXPECT_EQ(empty.exit_code, 1) << empty.output;
  EXPECT_THAT(empty.output, HasSubstr("cannot read the run log: /nonexistent/run/metrics.jsonl: cannot open file"));
}

TEST(CliFlagsTest, WorkerBinaryHasTheWorkerFlags) {
  const Result r = RunBinary(JUGGLE_WORKER_BINARY, "--help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* flag : {"--learner", "--envs", "--threads", "--slot", "--give_up_after",
                           "--keepalive_time", "--keepalive_timeout", "--max_reconnect_backoff",
                           "--min_connect_timeout", "--keepalive_permit_without_calls",
                           "--max_chunks_in_flight"}) {
    EXPECT_THAT(r.output, HasSubstr(flag));
  }
  const Result bad = RunBinary(JUGGLE_WORKER_BINARY, "--envs=many");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

TEST(CliFlagsTest, KeepaliveFlagsOutOfRangeNameTheFlagAndExitTwo) {
  const Result worker = RunBinary(JUGGLE_WORKER_BINARY, "--keepalive_time=0.1");
  EXPECT_EQ(worker.exit_code, 2) << worker.output;
  EXPECT_THAT(worker.output, HasSubstr("--keepalive_time"));
  EXPECT_THAT(worker.output, HasSubstr("0 (off) or in [0.5, 86400]"));
  const Result backoff = RunBinary(JUGGLE_WORKER_BINARY, "--max_reconnect_backoff=0.05");
  EXPECT_EQ(backoff.exit_code, 2) << backoff.output;
  EXPECT_THAT(backoff.output, HasSubstr("--max_reconnect_backoff"));
  for (const char* window : {"--max_chunks_in_flight=0", "--max_chunks_in_flight=257",
                             "--max_chunks_in_flight=four"}) {
    const Result bad = RunBinary(JUGGLE_WORKER_BINARY, window);
    EXPECT_EQ(bad.exit_code, 2) << window << ": " << bad.output;
    EXPECT_THAT(bad.output, HasSubstr("--max_chunks_in_flight"));
  }
  const Result learner = Juggle("learner --min_worker_ping_interval=-3");
  EXPECT_EQ(learner.exit_code, 2) << learner.output;
  EXPECT_THAT(learner.output, HasSubstr("--min_worker_ping_interval"));
  const Result help = Juggle("learner --help");
  EXPECT_THAT(help.output, HasSubstr("--keepalive_time"));
  EXPECT_THAT(help.output, HasSubstr("--min_worker_ping_interval"));
}

}  // namespace
}  // namespace juggle
