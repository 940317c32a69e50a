// The skill choice as a steering table: from every node, the first edge of a shortest path to the
// chosen node (and back to it from its own cycle); unknown and unreachable nodes refused.
#include "play/steering.h"

#include "envs/testing/test_configs.h"
#include "google/protobuf/text_format.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::play {
namespace {

using ::testing::HasSubstr;

TEST(SteeringTest, EveryNodeTakesTheFirstEdgeOfAShortestPathToTheChosenNode) {
  auto spec = testing::LoadSpec("foot_and_head_planner");
  ASSERT_NE(spec, nullptr);
  const ControlGraph& g = spec->graph();
  const int foot_down = *g.FindNode("right_foot_down"), foot_up = *g.FindNode("right_foot_up");
  const int head_down = *g.FindNode("head_down"), head_up = *g.FindNode("head_up");
  absl::StatusOr<std::vector<int>> to_head = SteerToward(g, "head_down", foot_down);
  ASSERT_TRUE(to_head.ok()) << to_head.status();
  EXPECT_EQ((*to_head)[foot_up], *g.FindEdge(foot_up, head_down));
  EXPECT_EQ((*to_head)[head_up], *g.FindEdge(head_up, head_down));  // the header repeats
  EXPECT_EQ((*to_head)[foot_down], *g.FindEdge(foot_down, foot_up));
  EXPECT_EQ((*to_head)[head_down], *g.FindEdge(head_down, head_up));
  absl::StatusOr<std::vector<int>> to_foot = SteerToward(g, "right_foot_down", head_down);
  ASSERT_TRUE(to_foot.ok());
  EXPECT_EQ((*to_foot)[head_up], *g.FindEdge(head_up, foot_down));
  EXPECT_EQ((*to_foot)[foot_up], *g.FindEdge(foot_up, foot_down));
  EXPECT_EQ(SteerableNodes(g).size(), 4u);
}

TEST(SteeringTest, RefusesAnUnknownNodeNamingIt) {
  auto spec = testing::LoadSpec("foot_and_head_planner");
  ASSERT_NE(spec, nullptr);
  absl::StatusOr<std::vector<int>> r = SteerToward(spec->graph(), "left_knee_down", 0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(r.status().message(), HasSubstr("no node \"left_knee_down\""));
}

TEST(SteeringTest, RefusesANodeNoEdgeLeadsIntoOrThatCannotBeReached) {
  // right_foot: foot juggles only; head_down is a start only (nothing leads into it), and
  // from its header cycle the foot cannot be reached.
  config::ControlGraph proto;
  ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(R"pb(
    node { name: "foot_down" stage: DOWN initial: true contact_body: "right_ankle"
           contact_height: 0.5 apex_height: 1.4 pose { leg_swing {} } }
    node { name: "foot_up" stage: UP contact_body: "right_ankle"
           contact_height: 0.5 apex_height: 1.4 pose { leg_swing {} } }
    node { name: "head_down" stage: DOWN initial: true contact_body: "neck"
           contact_height: 1.6 apex_height: 2.0 pose { head_dip {} } }
    node { name: "head_up" stage: UP contact_body: "neck"
           contact_height: 1.6 apex_height: 2.0 pose { head_dip {} } }
    node { name: "head_down2" stage: DOWN contact_body: "neck"
           contact_height: 1.6 apex_height: 2.0 pose { head_dip {} } }
    edge { from: "foot_down" to: "foot_up" }
    edge { from: "foot_up" to: "foot_down" }
    edge { from: "head_down" to: "head_up" }
    edge { from: "head_up" to: "head_down2" }
    edge { from: "head_down2" to: "head_up" }
  )pb", &proto));
  absl::StatusOr<ControlGraph> g = ControlGraph::Build(proto, SourceLocator("test"));
  ASSERT_TRUE(g.ok()) << g.status();
  absl::StatusOr<std::vector<int>> start_only = SteerToward(*g, "head_down", 0);
  ASSERT_FALSE(start_only.ok());
  EXPECT_THAT(start_only.status().message(), HasSubstr("no edge of the graph leads into"));
  absl::StatusOr<std::vector<int>> unreachable =
      SteerToward(*g, "foot_down", *g->FindNode("head_up"));
  ASSERT_FALSE(unreachable.ok());
  EXPECT_THAT(unreachable.status().message(), HasSubstr("cannot be reached from \"head_up\""));
  EXPECT_EQ(SteerableNodes(*g).size(), 4u);
}

}  // namespace
}  // namespace juggle::play
