// A change of skill between a header and the chest (NodeSpec.pose_lead_in, ComputeCursorPose;
// BaseController::UpdateHeadLean's receiving target): the next node's pose blended in over the
// end of the UP node before it, and a header aiming the ball at the node that receives it.
// Places are checked by MuJoCo's forward kinematics, not by the blend's own formula.
#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

using ::testing::HasSubstr;
using testing::ChestNodeFields;
using testing::SoccerSpecWithGraph;

// The header's and the chest's node fields (configs/graphs/headers.textproto, chest.textproto).
constexpr char kHead[] =
    " contact_body: \"neck\" contact_height: 1.75 apex_height: 2.0"
    " ball_target { x: 0.08 y: 0 } pose { head_dip { amplitude: 0.5 } }"
    " head_feedback { lean_per_m: 2.5 redirect: 1 }";
std::string ChestFields() {
  return ChestNodeFields() + " head_feedback { lean_per_m: 3 redirect: 1 contact_radius_m: 0.22 }";
}

// head_down -> head_up -> chest_down -> chest_up -> head_down; `lead_in` inside both DOWN
// nodes.
std::string HeadAndChestGraph(const std::string& lead_in) {
  return absl::StrCat(
      "node { name: \"head_down\" stage: DOWN initial: true", kHead, " ", lead_in, " }\n",
      "node { name: \"head_up\" stage: UP", kHead, " }\n",
      "node { name: \"chest_down\" stage: DOWN", ChestFields(), " ", lead_in, " }\n",
      "node { name: \"chest_up\" stage: UP", ChestFields(), " }\n",
      "edge { from: \"head_down\" to: \"head_up\" }\n"
      "edge { from: \"head_up\" to: \"chest_down\" }\n"
      "edge { from: \"chest_down\" to: \"chest_up\" }\n"
      "edge { from: \"chest_up\" to: \"head_down\" }\n");
}

// head_down -> head_up -> head_down.
std::string HeadersGraph() {
  return absl::StrCat("node { name: \"head_down\" stage: DOWN initial: true", kHead, " }\n",
                      "node { name: \"head_up\" stage: UP", kHead, " }\n",
                      "edge { from: \"head_down\" to: \"head_up\" }\n"
                      "edge { from: \"head_up\" to: \"head_down\" }\n");
}

using ::juggle::testing::HeadCentre;

CursorState Cursor(int current, int next) {
  CursorState c;
  c.current = current;
  c.next = next;
  return c;
}

TEST(SkillChangeTest, TheChestsLeanBlendsInOverTheLastShareOfTheHeadersRise) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
      SoccerSpecWithGraph(HeadAndChestGraph("pose_lead_in: 0.5"));
  ASSERT_TRUE(spec.ok()) << spec.status();
  const JuggleSpec& s = **spec;
  const CursorState rising = Cursor(/*head_up=*/1, /*chest_down=*/2);
  auto pose_at = [&](double phase) {
    CharacterPose pose;
    ComputeCursorPose(s, rising, phase, &pose);
    return pose;
  };
  CharacterPose header, chest;
  ComputeReferencePose(s, 1, 0.7, &header);
  ComputeReferencePose(s, 2, 0.0, &chest);
  // Before the last half of the rise: the header's pose, bit for bit.
  EXPECT_EQ(pose_at(0.7), header);
  // At the apex: the chest's pose at its node's start.
  const CharacterPose apex = pose_at(1.0);
  for (int i = 0; i < kCharacterNq; ++i) EXPECT_NEAR(apex[i], chest[i], 1e-9) << i;
  // On the way the head goes back monotonically from the header's place to the chest's.
  double previous = HeadCentre(s, header)[0];
  const double leaned = HeadCentre(s, chest)[0];
  ASSERT_LT(leaned, previous - 0.1);  // the chest's lean takes the head well back
  for (const double phase : {0.8, 0.85, 0.9, 0.95}) {
    SCOPED_TRACE(phase);
    const double x = HeadCentre(s, pose_at(phase))[0];
    EXPECT_LT(x, previous);
    EXPECT_GT(x, leaned);
    previous = x;
  }
}

TEST(SkillChangeTest, WithoutALeadInTheUpNodeKeepsItsOwnPoseToTheApex) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
      SoccerSpecWithGraph(HeadAndChestGraph(""));
  ASSERT_TRUE(spec.ok()) << spec.status();
  for (const double phase : {0.6, 0.9, 0.999}) {
    CharacterPose own, cursor;
    ComputeReferencePose(**spec, 1, phase, &own);
    ComputeCursorPose(**spec, Cursor(1, 2), phase, &cursor);
    EXPECT_EQ(cursor, own) << phase;
  }
  // A DOWN node never blends, even when the next node sets a lead-in.
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> led =
      SoccerSpecWithGraph(HeadAndChestGraph("pose_lead_in: 1"));
  ASSERT_TRUE(led.ok()) << led.status();
  CharacterPose own, cursor;
  ComputeReferencePose(**led, 2, 0.4, &own);
  ComputeCursorPose(**led, Cursor(2, 3), 0.4, &cursor);
  EXPECT_EQ(cursor, own);
}

TEST(SkillChangeTest, TheEnvTracksTheBlendedPoseBeforeTheApex) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
      SoccerSpecWithGraph(HeadAndChestGraph("pose_lead_in: 0.5"));
  ASSERT_TRUE(spec.ok()) << spec.status();
  AdaptiveWalk walk(&(*spec)->graph());
  JuggleEnv env(*spec, Rng(5));
  env.ResetAt(/*head_up=*/1, walk);  // an UP node starts at φ = 0.5
  ASSERT_EQ(env.cursor().next, 2);
  const double upright = HeadCentre(**spec, env.state().reference)[0] - env.data()->qpos[0];
  // The reference of the header's last step (a step's reference is its starting phase's).
  double late = upright;
  for (int step = 0; step < 100; ++step) {
    env.Step(kZeroAction, walk);
    if (env.node() != 1) break;
    late = HeadCentre(**spec, env.state().reference)[0] - env.data()->qpos[0];
  }
  ASSERT_EQ(env.node(), 2);
  EXPECT_LT(late, upright - 0.1);  // the head already well back in the reference
}

TEST(SkillChangeTest, AHeaderAimsTheBallAtTheNodeThatReceivesIt) {
  // The same ball straight down over the header's target: a header-only graph keeps the head
  // where it is; before the chest the head goes ahead of the ball so the bounce sends it back
  // toward the chest's target, 0.17 m behind.
  double pitch[2];
  for (int g = 0; g < 2; ++g) {
    const std::string graph = g == 0 ? HeadersGraph() : HeadAndChestGraph("");
    absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(graph);
    ASSERT_TRUE(spec.ok()) << spec.status();
    AdaptiveWalk walk(&(*spec)->graph());
    JuggleEnv env(*spec, Rng(3));
    env.ResetAt(0, walk);
    mjData* d = env.data();
    double* ball = d->qpos + (*spec)->ball_qpos();
    double* v = d->qvel + (*spec)->ball_dof();
    ball[0] = d->qpos[0] + 0.08;
    ball[1] = d->qpos[1];
    ball[2] = 2.0;
    v[0] = v[1] = 0;
    v[2] = -1;
    env.Step(kZeroAction, walk);
    pitch[g] = env.state().swing_adjust.lean_pitch;
  }
  EXPECT_NEAR(pitch[0], 0, 1e-9);
  EXPECT_LT(pitch[1], -0.02);  // forward is a negative pitch about the chest's z
}

TEST(SkillChangeTest, ALeadInOnAnUpNodeIsAConfigErrorNamingTheNodeAndField) {
  std::string graph = HeadAndChestGraph("");
  const std::string up = "node { name: \"head_up\" stage: UP";
  graph.insert(graph.find(up) + up.size(), " pose_lead_in: 0.5");
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(graph);
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("node 'head_up'"));
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("pose_lead_in"));
}

}  // namespace
}  // namespace juggle::soccer_juggle
