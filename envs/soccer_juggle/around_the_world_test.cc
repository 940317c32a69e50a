// Around-the-world (NodeSpec.around_the_world, docs/planner.md "Around-the-world"): the foot–ball
// angle's violation that the planner scores (JuggleEnv::AroundTheWorldViolation) against the
// episode's end and against a hand-made state, and keyframes' swing_side (the base controller
// balancing on the other foot). graphs/foot_and_atw.textproto on the right-foot planner's config.
#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_replace.h"
#include "envs/soccer_juggle/base_controller.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/outcomes.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

std::string AtwGraphText(bool swing_side) {
  const std::string text = testing::ReadRepoFile("configs/graphs/foot_and_atw.textproto");
  if (!swing_side) return text;
  return absl::StrReplaceAll(text, {{"keyframes {\n", "keyframes {\n      swing_side: RIGHT\n"}});
}

std::shared_ptr<const JuggleSpec> AtwSpec(bool swing_side) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
      testing::SoccerSpecWithGraph(AtwGraphText(swing_side));
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

TEST(AroundTheWorldTest, TheViolationPassesOneExactlyWhereTheEpisodeEndsForTheAngle) {
  const std::shared_ptr<const JuggleSpec> spec = AtwSpec(false);
  ASSERT_NE(spec, nullptr);
  AdaptiveWalk walk(&spec->graph());
  int checked = 0, ended_for_the_angle = 0;
  for (int seed = 0; seed < 6; ++seed) {
    JuggleEnv env(spec, Rng(seed));
    env.ResetAt(*spec->graph().FindNode("right_atw_down"), walk);
    for (int t = 0; t < 150; ++t) {
      const StepResult r = env.Step(kZeroAction, walk);
      const double v = env.AroundTheWorldViolation();
      const bool atw = spec->node_runtime(env.node()).atw_foot_body >= 0;
      if (!atw) {
        EXPECT_EQ(v, 0.0) << "a foot juggle's node checks no angle";
      }
      if (v > 0) ++checked;
      if (r.outcome == kAroundTheWorld) {
        EXPECT_GT(v, 1.0) << "seed " << seed << " step " << t;
        ++ended_for_the_angle;
      } else if (r.outcome == Outcome::kRunning) {
        EXPECT_LE(v, 1.0) << "seed " << seed << " step " << t;
      }
      if (r.terminated()) break;
    }
  }
  EXPECT_GT(checked, 20) << "the angle should be checked over most of the nodes' steps";
  EXPECT_GT(ended_for_the_angle, 0) << "zero action loses the circle on some of these starts";
}

TEST(AroundTheWorldTest, TheBallMirroredThroughTheFootTurnsTheAngleHalfwayRound) {
  const std::shared_ptr<const JuggleSpec> spec = AtwSpec(false);
  ASSERT_NE(spec, nullptr);
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(3));
  const int node = *spec->graph().FindNode("right_atw_down");
  env.ResetAt(node, walk);
  for (int t = 0; t < 4; ++t) ASSERT_FALSE(env.Step(kZeroAction, walk).terminated());
  const double before = env.AroundTheWorldViolation();
  ASSERT_GT(before, 0.0) << "a few steps into the node its angle is checked";
  ASSERT_LT(before, 1.0);
  // |e^{i(ψ+π)} − e^{iψd}|² = 4 − |e^{iψ} − e^{iψd}|², and the bound's chord² is 2 − 2 cos 60° = 1.
  const NodeRuntime& rt = spec->node_runtime(node);
  EXPECT_NEAR(rt.atw_max_chord2, 1.0, 1e-12);
  mjData* d = env.data();
  const double* foot = d->xpos + 3 * rt.atw_foot_body;
  double* ball = d->qpos + spec->ball_qpos();
  for (int c = 1; c < 3; ++c) ball[c] = 2 * foot[c] - ball[c];
  EXPECT_NEAR(env.AroundTheWorldViolation(), 4.0 - before, 1e-9);
}

// The balance's torques alone (no reference feed-forward) at the start of right_atw_down.
std::vector<double> BalanceTorques(const std::shared_ptr<const JuggleSpec>& spec) {
  LoadedConfig config = spec->config();
  config.run.mutable_soccer_juggle()->mutable_env()->set_reference_feedforward(0);
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> balance_only = JuggleSpec::Create(config);
  EXPECT_TRUE(balance_only.ok()) << balance_only.status();
  AdaptiveWalk walk(&(*balance_only)->graph());
  JuggleEnv env(*balance_only, Rng(3));
  env.ResetAt(*(*balance_only)->graph().FindNode("right_atw_down"), walk);
  for (int t = 0; t < 3; ++t) EXPECT_FALSE(env.Step(kZeroAction, walk).terminated());
  BaseController base(**balance_only);
  std::vector<double> tau(kCharacterNv, 0.0);
  base.AddFeedforward(env.cursor(), env.reference_pose(), env.state().swing_adjust, env.data(),
                      tau.data());
  return tau;
}

double JointTorque(const JuggleSpec& spec, humanoid::JointId joint,
                   const std::vector<double>& tau) {
  const ActuatedJoint& j = spec.joint(joint);
  double sum = 0;
  for (int k = j.dof_adr; k < j.dof_adr + j.dofs; ++k) sum += std::abs(tau[k]);
  return sum;
}

TEST(AroundTheWorldTest, KeyframesWithASwingSideBalanceOnTheOtherFootAlone) {
  const std::shared_ptr<const JuggleSpec> both = AtwSpec(false);
  const std::shared_ptr<const JuggleSpec> one = AtwSpec(true);
  ASSERT_NE(both, nullptr);
  ASSERT_NE(one, nullptr);
  const std::vector<double> two_feet = BalanceTorques(both);
  const std::vector<double> left_foot = BalanceTorques(one);
  // Both feet down: half of each gain through each ankle and hip.
  EXPECT_GT(JointTorque(*both, kRightAnkle, two_feet), 0.0);
  EXPECT_GT(JointTorque(*both, kLeftAnkle, two_feet), 0.0);
  // The right leg circles: the balance acts through the left ankle and hip only.
  EXPECT_EQ(JointTorque(*one, kRightAnkle, left_foot), 0.0);
  EXPECT_EQ(JointTorque(*one, kRightHip, left_foot), 0.0);
  EXPECT_GT(JointTorque(*one, kLeftAnkle, left_foot), 0.0);
  EXPECT_GT(JointTorque(*one, kLeftHip, left_foot), 0.0);
}

}  // namespace
}  // namespace juggle::soccer_juggle
