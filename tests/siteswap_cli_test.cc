// `juggle siteswap` end to end: runs the built binary and checks its exit status, the reason it
// gives for an invalid pattern, and the key=value last line.
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
  std::string last_line;
};

// Runs `juggle <args>` through the shell; args must need no quoting beyond what is given.
Result RunJuggle(const std::string& args) {
  Result r;
  const std::string command = std::string(JUGGLE_BINARY) + " " + args + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), pipe)) > 0) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::string trimmed = r.output;
  while (!trimmed.empty() && trimmed.back() == '\n') trimmed.pop_back();
  const size_t nl = trimmed.rfind('\n');
  r.last_line = nl == std::string::npos ? trimmed : trimmed.substr(nl + 1);
  return r;
}

TEST(SiteswapCliTest, ValidPatternExitsZeroWithBallsOnTheLastLine) {
  const Result r = RunJuggle("siteswap 531");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.last_line, HasSubstr("valid=1"));
  EXPECT_THAT(r.last_line, HasSubstr("balls=3"));
  EXPECT_EQ(r.last_line, "valid=1 pattern=531 balls=3 period=3 max_throw=5 state=xxx-- ground=1");
  // The schedule row of the right hand's 5 (Eq. 1-3 at the defaults).
  EXPECT_THAT(r.output, HasSubstr("   0    0     5   R>L toss       0.000     0.900    0.900    "
                                  "4.415    0.444   0.993"));
}

TEST(SiteswapCliTest, InvalidPatternExitsOneNamingTheCollision) {
  const Result r = RunJuggle("siteswap 543");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("throws at positions 0 ('5'), 1 ('4') and 2 ('3') all land on "
                                  "beat 2 (mod 3)"));
  EXPECT_THAT(r.last_line, StartsWith("valid=0"));
}

TEST(SiteswapCliTest, BadCharacterExitsOne) {
  const Result r = RunJuggle("siteswap 5_1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("invalid character '_' at position 1"));
  EXPECT_EQ(r.last_line, "valid=0 error=parse");
}

TEST(SiteswapCliTest, ExcitedPatternShowsItsStateAndEntry) {
  const Result r = RunJuggle("siteswap 51 --hand_period=0.4 --dwell_ratio=0.6");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("throw 4 to enter it; throw 2 to leave it"));
  EXPECT_EQ(r.last_line, "valid=1 pattern=51 balls=3 period=2 max_throw=5 state=xx-x- ground=0");
}

TEST(SiteswapCliTest, TransitionPrintsTheThrows) {
  Result r = RunJuggle("siteswap --transition 3 51");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.last_line, "valid=1 balls=3 from=3 to=51 length=1 transition=4");
  r = RunJuggle("siteswap --transition 3 441");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.last_line, "valid=1 balls=3 from=3 to=441 length=0 transition=");
  r = RunJuggle("siteswap --transition 3 5");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("both must juggle the same number of balls"));
  EXPECT_THAT(r.last_line, StartsWith("valid=0"));
}

TEST(SiteswapCliTest, EnumerateListsPatterns) {
  const Result r = RunJuggle("siteswap --enumerate --balls=3 --max_throw=5 --period=3");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* p : {"531", "522", "504", "441", "423"}) EXPECT_THAT(r.output, HasSubstr(p));
  EXPECT_EQ(r.last_line, "count=5 balls=3 max_throw=5 period=3");
  EXPECT_EQ(RunJuggle("siteswap --enumerate --balls=3 --max_throw=5 --max_period=3").last_line,
            "count=8 balls=3 max_throw=5 max_period=3");
}

TEST(SiteswapCliTest, UsageErrorsExitTwo) {
  for (const char* args : {"siteswap", "siteswap 3 4", "siteswap --transition 3",
                           "siteswap --bogus 3", "siteswap 3 --dwell_ratio=1.5",
                           "siteswap 3 --hand_period=abc", "siteswap --enumerate --balls=3",
                           "siteswap --enumerate --balls=3 --max_throw=5 --period=0",
                           "siteswap 3 --balls=3", "siteswap --transition --enumerate 3 4"}) {
    SCOPED_TRACE(args);
    const Result r = RunJuggle(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr("juggle siteswap --help"));
  }
  EXPECT_EQ(RunJuggle("siteswap --help").exit_code, 0);
}

}  // namespace
}  // namespace juggle
