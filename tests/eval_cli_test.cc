// `juggle eval` as a user runs it: the zero-action baseline's key=value line, and --record
// writing every episode one after another as a replayable trajectory.
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "gmock/gmock.h"
#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "record/trajectory.h"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

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

}  // namespace
}  // namespace juggle
