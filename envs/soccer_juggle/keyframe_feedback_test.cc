// The kick feedback on keyframes with a swing side (envs/soccer_juggle/reference_pose.cc
// OffsetKeyframedSwing, base_controller.cc UpdateSwingAdjust): the foot at the contact moves
// toward the ball's predicted crossing, checked by MuJoCo's forward kinematics; nothing moves
// where the node's cycle wraps, on the standing leg, or in frames without a swing side; the
// timing shifts the frames' phase, clamped at the ends. graphs/around_the_world.textproto.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_replace.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

// The shipped graph, its DOWN node's own kick feedback (the timing) kept or taken out.
std::string AtwGraph(bool own_feedback = false) {
  const std::string shipped = "  kick_feedback { timing: 1 }\n";
  std::string graph = testing::ReadRepoFile("configs/graphs/around_the_world.textproto");
  EXPECT_NE(graph.find(shipped), std::string::npos);
  return own_feedback ? graph : absl::StrReplaceAll(graph, {{shipped, ""}});
}

std::shared_ptr<const JuggleSpec> Spec(const std::string& graph) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = testing::SoccerSpecWithGraph(graph);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

CharacterPose PoseAt(const JuggleSpec& spec, int node, double phase, const SwingAdjust& adjust) {
  CharacterPose pose;
  ComputeReferencePose(spec, node, phase, &pose, adjust);
  return pose;
}

// World position of `body` in `pose`, by MuJoCo's forward kinematics.
std::array<double, 3> BodyAt(const JuggleSpec& spec, const CharacterPose& pose, const char* body) {
  MjDataPtr data(mj_makeData(spec.model()));
  std::copy(pose.begin(), pose.end(), data->qpos);
  mj_kinematics(spec.model(), data.get());
  const double* x = data->xpos + 3 * mj_name2id(spec.model(), mjOBJ_BODY, body);
  return {x[0], x[1], x[2]};
}

double MaxDifference(const CharacterPose& a, const CharacterPose& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

TEST(KeyframeFeedbackTest, TheFootAtTheContactMovesTowardTheBallAndTheStandingFootStays) {
  const std::shared_ptr<const JuggleSpec> spec = Spec(AtwGraph());
  ASSERT_NE(spec, nullptr);
  const int down = *spec->graph().FindNode("right_atw_down");
  const CharacterPose plain = PoseAt(*spec, down, 0.5, {});
  const std::array<double, 3> foot = BodyAt(*spec, plain, "right_ankle");
  const std::array<double, 3> stand = BodyAt(*spec, plain, "left_ankle");
  // A ball crossing further forward: more hip flexion (the controller's sign) moves it +x.
  SwingAdjust forward;
  forward.hip = 0.2;
  const CharacterPose f = PoseAt(*spec, down, 0.5, forward);
  EXPECT_GT(BodyAt(*spec, f, "right_ankle")[0] - foot[0], 0.05);
  // A ball crossing to the character's left (+y): the right leg's abduction is −gain·e_y.
  SwingAdjust left;
  left.abduction = -0.2;
  const CharacterPose l = PoseAt(*spec, down, 0.5, left);
  EXPECT_GT(BodyAt(*spec, l, "right_ankle")[1] - foot[1], 0.05);
  for (const CharacterPose* moved : {&f, &l}) {
    const std::array<double, 3> s = BodyAt(*spec, *moved, "left_ankle");
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(s[i], stand[i], 1e-12) << "standing foot axis " << i;
  }
  // Where the cycle wraps the authored frame is kept.
  forward.knee = 0.3;
  EXPECT_LT(MaxDifference(PoseAt(*spec, down, 0.0, forward), PoseAt(*spec, down, 0.0, {})),
            1e-12);
  EXPECT_LT(MaxDifference(PoseAt(*spec, down, 1.0, forward), PoseAt(*spec, down, 1.0, {})),
            1e-12);
}

TEST(KeyframeFeedbackTest, FramesWithoutASwingSideIgnoreTheAdjustment) {
  const std::string graph = absl::StrReplaceAll(AtwGraph(), {{"swing_side: RIGHT", ""}});
  const std::shared_ptr<const JuggleSpec> spec = Spec(graph);
  ASSERT_NE(spec, nullptr);
  const int down = *spec->graph().FindNode("right_atw_down");
  SwingAdjust adjust;
  adjust.hip = 0.2;
  adjust.abduction = -0.2;
  adjust.phase = 0.05;
  EXPECT_EQ(MaxDifference(PoseAt(*spec, down, 0.4, adjust), PoseAt(*spec, down, 0.4, {})), 0.0);
}

TEST(KeyframeFeedbackTest, TheTimingShiftsTheFramesAndHoldsTheEndFramesPastTheEnds) {
  const std::shared_ptr<const JuggleSpec> spec = Spec(AtwGraph());
  ASSERT_NE(spec, nullptr);
  const int down = *spec->graph().FindNode("right_atw_down");
  SwingAdjust later;
  later.phase = -0.05;
  EXPECT_LT(MaxDifference(PoseAt(*spec, down, 0.3, later), PoseAt(*spec, down, 0.25, {})), 1e-12);
  EXPECT_LT(MaxDifference(PoseAt(*spec, down, 0.02, later), PoseAt(*spec, down, 0.0, {})), 1e-12);
  SwingAdjust earlier;
  earlier.phase = 0.05;
  EXPECT_LT(MaxDifference(PoseAt(*spec, down, 0.98, earlier), PoseAt(*spec, down, 1.0, {})),
            1e-12);
}

TEST(KeyframeFeedbackTest, AKeyframeNodeTakesKickFeedbackOnlyWithASwingSide) {
  const std::string with = AtwGraph(/*own_feedback=*/true);
  EXPECT_NE(Spec(with), nullptr);
  const std::string without = absl::StrReplaceAll(with, {{"swing_side: RIGHT", ""}});
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> refused =
      testing::SoccerSpecWithGraph(without);
  ASSERT_FALSE(refused.ok());
  EXPECT_THAT(std::string(refused.status().message()),
              ::testing::HasSubstr("keyframes with a swing_side"));
}

// The base controller on the shipped graph (its DOWN node's own feedback: the timing alone):
// a ball held higher than the nominal flight arrives later, so the frames are shifted later —
// by at most a tenth of the cycle — and the joints are not moved.
TEST(KeyframeFeedbackTest, ALateBallShiftsTheFramesLaterWithinATenthOfTheCycle) {
  const std::shared_ptr<const JuggleSpec> spec = Spec(AtwGraph(/*own_feedback=*/true));
  ASSERT_NE(spec, nullptr);
  const int down = *spec->graph().FindNode("right_atw_down");
  const float zero[kNumActions] = {0};
  double shift[2], on_time = 0;
  for (int k = 0; k < 2; ++k) {
    AdaptiveWalk walk(&spec->graph());
    JuggleEnv env(spec, Rng(5));
    env.ResetAt(down, walk);
    const double nominal_height = env.data()->qpos[spec->ball_qpos() + 2];
    env.Step(zero, walk);
    if (k == 0) {
      on_time = env.state().swing_adjust.phase;
      EXPECT_LT(std::abs(on_time), 0.05) << "the start's ball is near its nominal flight";
    }
    // Raise the ball (k = 0: by 5 cm, k = 1: by 2 m) and stop it: it arrives later.
    double* ball = env.data()->qpos + spec->ball_qpos();
    ball[2] = nominal_height + (k == 0 ? 0.05 : 2.0);
    mju_zero(env.data()->qvel + spec->ball_dof(), 6);
    env.Step(zero, walk);
    shift[k] = env.state().swing_adjust.phase;
    EXPECT_EQ(env.state().swing_adjust.hip, 0.0);
    EXPECT_EQ(env.state().swing_adjust.abduction, 0.0);
  }
  EXPECT_LT(shift[0], on_time - 0.01);
  EXPECT_GT(shift[0], -0.1);
  EXPECT_EQ(shift[1], -0.1);
}

}  // namespace
}  // namespace juggle::soccer_juggle
