// Adaptive random walk (paper §5.2): the counting rule, count snapshots and sampling.
#include "common/adaptive_walk.h"

#include <cmath>
#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "google/protobuf/text_format.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// hub (DOWN) has three ways out: a (w0 1), b (w0 1), stall (w0 1); stall loops on itself with
// w0 30. Edge indices follow the order below.
constexpr char kGraph[] = R"pb(
  node { name: "hub" stage: DOWN initial: true contact_body: "right_ankle"
         contact_height: 0.5 apex_height: 1.4 pose { leg_swing {} } }
  node { name: "a" stage: UP contact_body: "right_ankle"
         contact_height: 0.5 apex_height: 1.4 pose { leg_swing {} } }
  node { name: "b" stage: UP contact_body: "right_ankle"
         contact_height: 0.5 apex_height: 1.4 pose { leg_swing {} } }
  node { name: "stall" stage: STALL contact_body: "right_ankle"
         contact_height: 0.5 stall { body: "right_ankle" } pose { leg_swing {} } }
  edge { from: "hub" to: "a" }          # 0
  edge { from: "hub" to: "b" }          # 1
  edge { from: "hub" to: "stall" }      # 2
  edge { from: "a" to: "hub" }          # 3
  edge { from: "b" to: "hub" }          # 4
  edge { from: "stall" to: "stall" weight: 30 }  # 5
  edge { from: "stall" to: "a" }        # 6
)pb";
constexpr int kHubToA = 0, kHubToB = 1, kHubToStall = 2, kStallLoop = 5, kStallToA = 6;

ControlGraph MakeGraph() {
  config::ControlGraph proto;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(kGraph, &proto));
  absl::StatusOr<ControlGraph> graph = ControlGraph::Build(proto, SourceLocator("test"));
  EXPECT_TRUE(graph.ok()) << graph.status();
  return *std::move(graph);
}

class AdaptiveWalkTest : public ::testing::Test {
 protected:
  void Apply(int edge, EdgeEventType type, int times = 1) {
    for (int i = 0; i < times; ++i) ASSERT_TRUE(walk_.Apply({edge, type}).ok());
  }
  ControlGraph graph_ = MakeGraph();
  AdaptiveWalk walk_{&graph_};
};

TEST_F(AdaptiveWalkTest, CountsStartAtTheBaseWeights) {
  EXPECT_EQ(walk_.counts(), std::vector<double>({1, 1, 1, 1, 1, 30, 1}));
}

TEST_F(AdaptiveWalkTest, ChosenEdgeGainsOneBaseWeight) {
  Apply(kHubToA, EdgeEventType::kChosen);
  EXPECT_EQ(walk_.count(kHubToA), 2.0);
  Apply(kHubToA, EdgeEventType::kChosen);
  EXPECT_EQ(walk_.count(kHubToA), 3.0);
  EXPECT_EQ(walk_.count(kHubToB), 1.0);  // other edges untouched
}

TEST_F(AdaptiveWalkTest, CompletedEdgeLosesTwoBaseWeights) {
  Apply(kHubToA, EdgeEventType::kChosen, 4);  // 5
  Apply(kHubToA, EdgeEventType::kCompleted);
  EXPECT_EQ(walk_.count(kHubToA), 3.0);
}

TEST_F(AdaptiveWalkTest, ChosenThenCompletedNetsMinusOneBaseWeight) {
  Apply(kHubToA, EdgeEventType::kChosen, 5);  // 6
  Apply(kHubToA, EdgeEventType::kChosen);     // 7: traversed ...
  Apply(kHubToA, EdgeEventType::kCompleted);  // 5: ... and completed
  EXPECT_EQ(walk_.count(kHubToA), 5.0);
}

TEST_F(AdaptiveWalkTest, FailedLeavesTheCountUnchanged) {
  Apply(kHubToA, EdgeEventType::kChosen, 2);  // 3
  Apply(kHubToA, EdgeEventType::kFailed);
  EXPECT_EQ(walk_.count(kHubToA), 3.0);
}

TEST_F(AdaptiveWalkTest, CountNeverDropsBelowTheBaseWeight) {
  Apply(kHubToA, EdgeEventType::kCompleted);
  EXPECT_EQ(walk_.count(kHubToA), 1.0);
  Apply(kHubToA, EdgeEventType::kChosen);     // 2
  Apply(kHubToA, EdgeEventType::kCompleted);  // 0 -> clamped to 1
  EXPECT_EQ(walk_.count(kHubToA), 1.0);
}

TEST_F(AdaptiveWalkTest, CountNeverExceedsAHundredBaseWeights) {
  Apply(kHubToA, EdgeEventType::kChosen, 150);
  EXPECT_EQ(walk_.count(kHubToA), 100.0);
  Apply(kHubToA, EdgeEventType::kCompleted);
  EXPECT_EQ(walk_.count(kHubToA), 98.0);
}

TEST_F(AdaptiveWalkTest, BaseWeightThirtyScalesStepsAndBounds) {
  Apply(kStallLoop, EdgeEventType::kChosen);
  EXPECT_EQ(walk_.count(kStallLoop), 60.0);
  Apply(kStallLoop, EdgeEventType::kChosen, 2);  // 120
  Apply(kStallLoop, EdgeEventType::kCompleted);  // 60
  EXPECT_EQ(walk_.count(kStallLoop), 60.0);
  Apply(kStallLoop, EdgeEventType::kCompleted);  // 0 -> 30
  EXPECT_EQ(walk_.count(kStallLoop), 30.0);
  Apply(kStallLoop, EdgeEventType::kChosen, 200);
  EXPECT_EQ(walk_.count(kStallLoop), 3000.0);
  Apply(kStallLoop, EdgeEventType::kFailed);
  EXPECT_EQ(walk_.count(kStallLoop), 3000.0);
}

TEST_F(AdaptiveWalkTest, ApplyOnUnknownEdgeIsInvalidArgument) {
  for (int edge : {7, 100, -1}) {
    const absl::Status s = walk_.Apply({edge, EdgeEventType::kChosen});
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << edge;
    EXPECT_THAT(s.message(), HasSubstr("edge event for unknown edge " + std::to_string(edge) +
                                       " (graph has 7 edges)"));
  }
  EXPECT_EQ(walk_.counts(), std::vector<double>({1, 1, 1, 1, 1, 30, 1}));
}

TEST_F(AdaptiveWalkTest, SetCountsReplacesEveryCount) {
  const std::vector<double> counts = {2, 50, 100, 1, 3, 3000, 7};
  ASSERT_TRUE(walk_.SetCounts(counts).ok());
  EXPECT_EQ(walk_.counts(), counts);
}

TEST_F(AdaptiveWalkTest, SetCountsRejectsAWrongSize) {
  const absl::Status s = walk_.SetCounts({1, 1, 1});
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "edge counts have 3 entries, the graph has 7 edges");
  EXPECT_EQ(walk_.count(kStallLoop), 30.0);  // unchanged
}

TEST_F(AdaptiveWalkTest, SetCountsRejectsACountBelowTheBaseWeight) {
  const absl::Status s = walk_.SetCounts({1, 1, 1, 1, 1, 29, 1});
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "edge count 29 of edge 5 lies outside [30, 3000]");
}

TEST_F(AdaptiveWalkTest, SetCountsRejectsACountAboveAHundredBaseWeights) {
  const absl::Status s = walk_.SetCounts({1, 101, 1, 1, 1, 30, 1});
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "edge count 101 of edge 1 lies outside [1, 100]");
  EXPECT_EQ(walk_.count(kHubToB), 1.0);  // nothing applied
}

TEST_F(AdaptiveWalkTest, SetCountsRejectsNaN) {
  const absl::Status s = walk_.SetCounts({1, 1, std::nan(""), 1, 1, 30, 1});
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(s.message(), HasSubstr("of edge 2 lies outside [1, 100]"));
}

TEST_F(AdaptiveWalkTest, ProbabilityIsCountOverTheSourceNodesTotal) {
  ASSERT_TRUE(walk_.SetCounts({1, 3, 6, 1, 1, 90, 10}).ok());
  EXPECT_DOUBLE_EQ(walk_.Probability(kHubToA), 0.1);
  EXPECT_DOUBLE_EQ(walk_.Probability(kHubToB), 0.3);
  EXPECT_DOUBLE_EQ(walk_.Probability(kHubToStall), 0.6);
  EXPECT_DOUBLE_EQ(walk_.Probability(kStallLoop), 0.9);
  EXPECT_DOUBLE_EQ(walk_.Probability(kStallToA), 0.1);
}

TEST_F(AdaptiveWalkTest, SampleEdgeOnlyReturnsOutgoingEdgesOfTheNode) {
  Rng rng(5);
  const int stall = *graph_.FindNode("stall");
  for (int i = 0; i < 1000; ++i) {
    const int e = walk_.SampleEdge(stall, &rng);
    ASSERT_TRUE(e == kStallLoop || e == kStallToA) << e;
  }
}

TEST_F(AdaptiveWalkTest, SamplingFrequenciesAreProportionalToCounts) {
  ASSERT_TRUE(walk_.SetCounts({1, 3, 6, 1, 1, 30, 1}).ok());
  const int hub = *graph_.FindNode("hub");
  constexpr int kDraws = 20000;
  int hits[3] = {0, 0, 0};
  Rng rng(1234);
  for (int i = 0; i < kDraws; ++i) {
    const int e = walk_.SampleEdge(hub, &rng);
    ASSERT_GE(e, kHubToA);
    ASSERT_LE(e, kHubToStall);
    ++hits[e];
  }
  const double p[3] = {0.1, 0.3, 0.6};
  double chi2 = 0;
  for (int e = 0; e < 3; ++e) {
    const double expected = p[e] * kDraws;
    chi2 += (hits[e] - expected) * (hits[e] - expected) / expected;
    EXPECT_NEAR(static_cast<double>(hits[e]) / kDraws, p[e], 0.02) << "edge " << e;
  }
  EXPECT_LT(chi2, 13.8);  // χ² with 2 degrees of freedom, p = 0.001
}

TEST_F(AdaptiveWalkTest, ChosenEventsShiftTheSamplingTowardTheEdge) {
  // After 98 kChosen on hub -> a its count is 99 of 101: nearly every draw takes it.
  Apply(kHubToA, EdgeEventType::kChosen, 98);
  const int hub = *graph_.FindNode("hub");
  Rng rng(77);
  int to_a = 0;
  for (int i = 0; i < 10000; ++i) to_a += walk_.SampleEdge(hub, &rng) == kHubToA;
  EXPECT_NEAR(to_a / 10000.0, 99.0 / 101.0, 0.01);
}

TEST_F(AdaptiveWalkTest, ASteeredNodeAlwaysTakesItsEdgeAndOthersStillSample) {
  std::vector<int> steering(graph_.num_nodes(), -1);
  steering[*graph_.FindNode("hub")] = kHubToB;
  ASSERT_TRUE(walk_.SetSteering(steering).ok());
  Rng rng(3), unsteered_rng(3);
  int stall_loops = 0;
  for (int i = 0; i < 2000; ++i) {
    EXPECT_EQ(walk_.SampleEdge(*graph_.FindNode("hub"), &rng), kHubToB);
    (void)unsteered_rng.Uniform();
    stall_loops += walk_.SampleEdge(*graph_.FindNode("stall"), &rng) == kStallLoop;
    (void)unsteered_rng.Uniform();
  }
  EXPECT_GT(stall_loops, 1800);  // 30 : 1 unsteered
  EXPECT_LT(stall_loops, 2000);
  EXPECT_EQ(rng.Uniform(), unsteered_rng.Uniform());  // the stream advanced as unsteered
  ASSERT_TRUE(walk_.SetSteering({}).ok());
  int to_b = 0;
  for (int i = 0; i < 3000; ++i) to_b += walk_.SampleEdge(*graph_.FindNode("hub"), &rng) == kHubToB;
  EXPECT_NEAR(to_b / 3000.0, 1.0 / 3.0, 0.05);
}

TEST_F(AdaptiveWalkTest, RefusesSteeringOfTheWrongSizeOrWithAnEdgeLeavingAnotherNode) {
  EXPECT_THAT(walk_.SetSteering({0, 1}).message(), HasSubstr("the graph has 4"));
  std::vector<int> steering(graph_.num_nodes(), -1);
  steering[*graph_.FindNode("a")] = kHubToA;
  EXPECT_THAT(walk_.SetSteering(steering).message(), HasSubstr("does not leave node a"));
  EXPECT_TRUE(walk_.steering().empty());
}

}  // namespace
}  // namespace juggle
