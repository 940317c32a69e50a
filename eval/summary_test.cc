// Evaluation summaries: percentiles as numpy computes them, and the juggles distribution.
#include "eval/summary.h"

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(SummaryTest, PercentilesInterpolateBetweenOrderStatistics) {
  // numpy.percentile([1, 2, 3, 4, 10], [10, 50, 90]) = [1.4, 3, 7.6]
  const std::vector<double> v = {10, 2, 4, 1, 3};
  EXPECT_NEAR(Percentile(v, 0.1), 1.4, 1e-12);
  EXPECT_NEAR(Percentile(v, 0.5), 3.0, 1e-12);
  EXPECT_NEAR(Percentile(v, 0.9), 7.6, 1e-12);
  EXPECT_EQ(Percentile({}, 0.5), 0);
  EXPECT_EQ(Percentile({5}, 0.9), 5);
}

TEST(SummaryTest, JugglesDistributionOutcomesAndMetrics) {
  const std::vector<std::string> names = {"running", "time_limit", "diverged", "ball_lost"};
  std::vector<EpisodeResult> episodes;
  for (int j : {0, 4, 10, 25, 30}) {
    EpisodeResult e;
    e.juggles = j;
    e.steps = 50 * (j + 1);
    e.return_sum = j;
    e.completions = 2 * j;
    e.outcome = j >= 25 ? Outcome::kTimeLimit : FamilyOutcome(0);
    if (j == 0 || j == 4) e.ending_detail = j == 0 ? "floor" : "left_knee";
    if (j == 10) e.metrics.push_back({"apex_error", 0.3});
    if (j == 30) e.metrics.push_back({"apex_error", 0.1});
    episodes.push_back(e);
  }
  const EvalSummary s = Summarize(episodes, 0.02, names);
  EXPECT_EQ(s.episodes, 5);
  EXPECT_EQ(s.median_juggles, 10);
  EXPECT_NEAR(s.p10_juggles, 1.6, 1e-12);
  EXPECT_NEAR(s.p90_juggles, 28, 1e-12);
  EXPECT_NEAR(s.mean_juggles, 13.8, 1e-12);
  EXPECT_NEAR(s.frac_juggles_ge_10, 0.6, 1e-12);
  EXPECT_NEAR(s.frac_juggles_ge_20, 0.4, 1e-12);
  EXPECT_NEAR(s.mean_episode_s, (1 + 5 + 11 + 26 + 31) * 50 * 0.02 / 5, 1e-9);
  EXPECT_EQ(s.outcomes.at("ball_lost"), 3);
  EXPECT_EQ(s.outcomes.at("time_limit"), 2);
  EXPECT_NEAR(s.mean_metrics.at("apex_error"), 0.2, 1e-12);
  EXPECT_EQ(s.ending_details.size(), 2u);
  EXPECT_EQ(s.ending_details.at("ball_lost.floor"), 1);
  EXPECT_EQ(s.ending_details.at("ball_lost.left_knee"), 1);
  EXPECT_EQ(SummaryToJson(s)["ending_details"]["ball_lost.floor"], 1);
  const std::string line = SummaryLine(s);
  EXPECT_THAT(line, HasSubstr("median_juggles=10 p10_juggles=1.6 p90_juggles=28"));
  EXPECT_THAT(line, HasSubstr("frac_juggles_ge_10=0.600 frac_juggles_ge_20=0.400"));
  EXPECT_THAT(line, HasSubstr("ball_lost=3"));
  EXPECT_THAT(line, HasSubstr("ball_lost.floor=1 ball_lost.left_knee=1"));
  EXPECT_THAT(line, HasSubstr("mean_apex_error=0.2000"));
  // A family whose episode is one attempt (football): no juggle fields, the rest as before.
  const std::string attempts = SummaryLine(s, /*juggles=*/false);
  EXPECT_THAT(attempts, Not(HasSubstr("juggles")));
  EXPECT_THAT(attempts, HasSubstr("episodes=5 mean_return="));
  EXPECT_EQ(attempts.substr(attempts.find(" mean_return=")),
            line.substr(line.find(" mean_return=")));
}

}  // namespace
}  // namespace juggle
