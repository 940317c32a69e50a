// Metrics: Prometheus text rendering.
#include "common/metrics.h"

#include <cmath>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(MetricsTest, RendersLabelledCounterWithHelpAndType) {
  Metrics m;
  m.Declare("juggle_chunks_rejected_total", "counter", "Chunks rejected, by reason.");
  m.Add("juggle_chunks_rejected_total", 1, {{"reason", "nan"}});
  m.Add("juggle_chunks_rejected_total", 1, {{"reason", "nan"}});
  m.Add("juggle_chunks_rejected_total", 1, {{"reason", "shape"}});
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("# HELP juggle_chunks_rejected_total Chunks rejected, by reason.\n"
                              "# TYPE juggle_chunks_rejected_total counter\n"));
  EXPECT_THAT(text, HasSubstr("\njuggle_chunks_rejected_total{reason=\"nan\"} 2\n"));
  EXPECT_THAT(text, HasSubstr("\njuggle_chunks_rejected_total{reason=\"shape\"} 1\n"));
}

TEST(MetricsTest, RendersSeveralLabelsSortedByNameAndUnlabelledSeriesBare) {
  Metrics m;
  m.Declare("g", "gauge", "A gauge.");
  m.Set("g", 0.5);
  m.Set("g", 3, {{"slot", "1"}, {"host", "a"}});
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("\ng 0.5\n"));
  EXPECT_THAT(text, HasSubstr("\ng{host=\"a\",slot=\"1\"} 3\n"));
}

TEST(MetricsTest, SetReplacesAndAddAccumulates) {
  Metrics m;
  m.Declare("c", "counter", "c");
  m.Declare("g", "gauge", "g");
  m.Add("c", 2);
  m.Add("c", 3);
  m.Set("g", 7);
  m.Set("g", 4);
  EXPECT_EQ(m.Get("c"), 5);
  EXPECT_EQ(m.Get("g"), 4);
}

TEST(MetricsTest, HistogramBucketsAreCumulativeWithInfSumAndCount) {
  Metrics m;
  m.Declare("lag", "histogram", "Policy lag.", {1, 5, 10});
  for (double v : {0.5, 3.0, 7.0, 20.0}) m.Observe("lag", v);
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("# HELP lag Policy lag.\n# TYPE lag histogram\n"
                              "lag_bucket{le=\"1\"} 1\n"
                              "lag_bucket{le=\"5\"} 2\n"
                              "lag_bucket{le=\"10\"} 3\n"
                              "lag_bucket{le=\"+Inf\"} 4\n"
                              "lag_sum 30.5\n"
                              "lag_count 4\n"));
}

TEST(MetricsTest, HistogramValueOnABucketBoundaryCountsInThatBucket) {
  Metrics m;
  m.Declare("h", "histogram", "h", {0, 1});
  m.Observe("h", 0);
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("h_bucket{le=\"0\"} 1\n"));
  EXPECT_THAT(text, HasSubstr("h_bucket{le=\"1\"} 1\n"));
}

TEST(MetricsTest, EraseRemovesOnlyTheSeriesWithThatExactLabelValue) {
  Metrics m;
  m.Declare("age", "gauge", "Heartbeat age.");
  m.Set("age", 1.5, {{"slot", "1"}});
  m.Set("age", 2.5, {{"slot", "10"}});
  m.Set("age", 3.5, {{"slot", "0"}});
  m.Erase("age", "slot", "1");
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, Not(HasSubstr("age{slot=\"1\"}")));
  EXPECT_THAT(text, HasSubstr("age{slot=\"10\"} 2.5\n"));
  EXPECT_THAT(text, HasSubstr("age{slot=\"0\"} 3.5\n"));
  EXPECT_EQ(m.Get("age", {{"slot", "1"}}), 0);
  EXPECT_EQ(m.Get("age", {{"slot", "10"}}), 2.5);
}

TEST(MetricsTest, GetReturnsSeriesValuesHistogramCountAndZeroForUnknown) {
  Metrics m;
  m.Declare("c", "counter", "c");
  m.Declare("h", "histogram", "h", {1});
  m.Add("c", 4, {{"reason", "nan"}});
  m.Observe("h", 0.5);
  m.Observe("h", 2);
  EXPECT_EQ(m.Get("c", {{"reason", "nan"}}), 4);
  EXPECT_EQ(m.Get("c", {{"reason", "other"}}), 0);
  EXPECT_EQ(m.Get("c"), 0);
  EXPECT_EQ(m.Get("h"), 2);
  EXPECT_EQ(m.Get("never_declared"), 0);
}

TEST(MetricsTest, RendersNonFiniteValuesAsTheExpositionFormatSpellsThem) {
  Metrics m;
  m.Declare("loss", "gauge", "loss");
  m.Set("loss", std::nan(""), {{"k", "nan"}});
  m.Set("loss", HUGE_VAL, {{"k", "pos"}});
  m.Set("loss", -HUGE_VAL, {{"k", "neg"}});
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("loss{k=\"nan\"} NaN\n"));
  EXPECT_THAT(text, HasSubstr("loss{k=\"pos\"} +Inf\n"));
  EXPECT_THAT(text, HasSubstr("loss{k=\"neg\"} -Inf\n"));
}

TEST(MetricsTest, EscapesBackslashQuoteAndNewlineInLabelValues) {
  Metrics m;
  m.Declare("info", "gauge", "info");
  m.Set("info", 1, {{"config", "a\"b\\c\nd"}});
  EXPECT_THAT(m.RenderPrometheus(), HasSubstr("info{config=\"a\\\"b\\\\c\\nd\"} 1\n"));
}

TEST(MetricsTest, SeriesReturnsEachSeriesWithItsLabels) {
  Metrics m;
  m.Declare("rejected", "counter", "r");
  m.Add("rejected", 2, {{"reason", "invalid"}});
  m.Add("rejected", 3, {{"reason", "stale_version"}});
  const auto series = m.Series("rejected");
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].first.at("reason"), "invalid");
  EXPECT_EQ(series[0].second, 2);
  EXPECT_EQ(series[1].first.at("reason"), "stale_version");
  EXPECT_EQ(series[1].second, 3);
  EXPECT_TRUE(m.Series("never_declared").empty());
}

}  // namespace
}  // namespace juggle
