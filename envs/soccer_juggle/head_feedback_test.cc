// A header's head feedback (NodeSpec.head_feedback, BaseController::UpdateHeadLean) and the
// head dip's push (HeadDip.push): the chest leans the head toward the coming ball, placed so
// that the bounce sends the ball back to the target; the pushed dip still straightens the knees
// at the contact. Checked against the head's place in the reference pose by MuJoCo's forward
// kinematics, not against the formula's own numbers.
#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

using testing::SoccerSpecWithGraph;

// Two header nodes at this model's head (configs/graphs/headers.textproto) with `extra` inside
// each node (e.g. a head_feedback block) and `dip` as the head_dip's fields.
std::string HeaderGraph(const std::string& extra, const std::string& dip = "amplitude: 0.5") {
  std::string out;
  for (const char* stage : {"DOWN", "UP"}) {
    absl::StrAppend(&out, "node { name: \"head_", stage, "\" stage: ", stage,
                    std::string(stage) == "DOWN" ? " initial: true" : "",
                    " contact_body: \"neck\" contact_height: 1.75 apex_height: 2.0",
                    " ball_target { x: 0.08 y: 0 } pose { head_dip { ", dip, " } } ", extra,
                    " }\n");
  }
  return out + "edge { from: \"head_DOWN\" to: \"head_UP\" }\n"
               "edge { from: \"head_UP\" to: \"head_DOWN\" }\n";
}

using ::juggle::testing::HeadCentre;

struct Lean {
  SwingAdjust adjust;
  std::array<double, 2> head_shift{};  // the lean's move of the head in the reference (m)
  std::array<double, 2> crossing{};    // the ball's crossing of the contact height − the target
};

// One zero-action step of head_DOWN with the ball put `ahead`, `left` of the target at the
// crossing, `drop` m above the contact height, moving at (vx, vy, vz); the lean the feedback
// chose and how far it moved the reference's head.
Lean LeanFor(const std::shared_ptr<const JuggleSpec>& spec, double ahead, double left, double vx,
             double vy, double vz = -1.0, double drop = 0.3) {
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(3));
  env.ResetAt(0, walk);
  mjData* d = env.data();
  const double g = spec->env().gravity();
  const double t = (vz + std::sqrt(vz * vz + 2 * g * drop)) / g;  // until the crossing
  double* ball = d->qpos + spec->ball_qpos();
  double* v = d->qvel + spec->ball_dof();
  ball[0] = d->qpos[0] + 0.08 + ahead - vx * t;
  ball[1] = d->qpos[1] + left - vy * t;
  ball[2] = 1.75 + drop;
  v[0] = vx;
  v[1] = vy;
  v[2] = vz;
  Lean out;
  const double root[2] = {d->qpos[0], d->qpos[1]};
  out.crossing = {ball[0] + vx * t - root[0] - 0.08, ball[1] + vy * t - root[1]};
  env.Step(kZeroAction, walk);
  out.adjust = env.state().swing_adjust;
  // The reference at the step's phase with and without the lean.
  SwingAdjust upright = out.adjust;
  upright.lean_pitch = upright.lean_roll = 0;
  CharacterPose leaning, straight;
  ComputeReferencePose(*spec, env.node(), env.cursor().phase, &leaning, out.adjust);
  ComputeReferencePose(*spec, env.node(), env.cursor().phase, &straight, upright);
  const std::array<double, 3> a = HeadCentre(*spec, leaning), b = HeadCentre(*spec, straight);
  out.head_shift = {a[0] - b[0], a[1] - b[1]};
  return out;
}

TEST(HeadFeedbackTest, TheChestLeansTheHeadTowardABallComingDownAheadAndToTheLeft) {
  // redirect 0: the head's centre straight under the crossing; 2.5 rad/m is the reciprocal of
  // the chest joint's 0.4-m lever to the head's centre, so the head moves about the offset.
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
      SoccerSpecWithGraph(HeaderGraph("head_feedback { lean_per_m: 2.5 redirect: 0 }"));
  ASSERT_TRUE(spec.ok()) << spec.status();
  const Lean lean = LeanFor(*spec, 0.06, 0.04, 0, 0);
  EXPECT_LT(lean.adjust.lean_pitch, 0);  // forward is a negative pitch about the chest's z
  EXPECT_LT(lean.adjust.lean_roll, 0);   // left is a negative roll about its x
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE(i);
    EXPECT_GT(lean.head_shift[i], 0.7 * lean.crossing[i]);
    EXPECT_LT(lean.head_shift[i], 1.3 * lean.crossing[i]);
  }

  // Without a head feedback the same ball leaves the reference upright.
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> plain = SoccerSpecWithGraph(HeaderGraph(""));
  ASSERT_TRUE(plain.ok()) << plain.status();
  const Lean none = LeanFor(*plain, 0.06, 0.04, 0, 0);
  EXPECT_EQ(none.adjust.lean_pitch, 0);
  EXPECT_EQ(none.adjust.lean_roll, 0);
}

TEST(HeadFeedbackTest, TheRedirectMeetsTheBallOnTheSideItComesFromInProportionToItsSpeed) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
      SoccerSpecWithGraph(HeaderGraph("head_feedback { lean_per_m: 2.5 redirect: 1 }"));
  ASSERT_TRUE(spec.ok()) << spec.status();
  // Straight down onto the target: nothing to correct, the head stays where it is.
  const Lean still = LeanFor(*spec, 0, 0, 0, 0);
  EXPECT_NEAR(still.head_shift[0], 0, 1e-9);
  EXPECT_NEAR(still.head_shift[1], 0, 1e-9);
  // Over the target but drifting forward: the head goes ahead of the ball (the contact's normal
  // then points back), twice as far for twice the drift, and not sideways.
  const Lean slow = LeanFor(*spec, 0, 0, 0.2, 0);
  const Lean fast = LeanFor(*spec, 0, 0, 0.4, 0);
  EXPECT_GT(slow.head_shift[0], 0.002);
  EXPECT_NEAR(fast.adjust.lean_pitch / slow.adjust.lean_pitch, 2.0, 1e-6);
  EXPECT_NEAR(slow.head_shift[1], 0, 1e-3);
  // Drifting to the left: the head goes to the left of the ball.
  const Lean drifting_left = LeanFor(*spec, 0, 0, 0, 0.2);
  EXPECT_GT(drifting_left.head_shift[1], 0.002);
}

TEST(HeadFeedbackTest, TheLeanIsClampedToTheMaximumShift) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(
      HeaderGraph("head_feedback { lean_per_m: 2.5 redirect: 0 max_shift_m: 0.05 }"));
  ASSERT_TRUE(spec.ok()) << spec.status();
  const Lean far = LeanFor(*spec, 0.3, 0.4, 0, 0);  // 0.5 m away
  EXPECT_NEAR(std::hypot(far.adjust.lean_pitch, far.adjust.lean_roll), 2.5 * 0.05, 1e-9);
  EXPECT_NEAR(far.adjust.lean_roll / far.adjust.lean_pitch, 0.4 / 0.3, 1e-6);
}

TEST(HeadFeedbackTest, APushedDipStillStraightensTheKneesAtTheContact) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> pushed =
      SoccerSpecWithGraph(HeaderGraph("", "amplitude: 0.5 push: 0.03"));
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> plain = SoccerSpecWithGraph(HeaderGraph(""));
  ASSERT_TRUE(pushed.ok()) << pushed.status();
  ASSERT_TRUE(plain.ok()) << plain.status();
  const int knee = (*plain)->joint(kRightKnee).qpos_adr;
  auto knee_at = [&](const JuggleSpec& spec, int node, double phase) {
    CharacterPose pose;
    ComputeReferencePose(spec, node, phase, &pose);
    return pose[knee];
  };
  // Without a push the legs are straight at the contact (φ = 0.5).
  EXPECT_NEAR(knee_at(**plain, 0, 0.4999), 0, 0.01);
  // With one they are still bent there and straightening (the knee angle, ≤ 0, rising), and
  // straight from the dip's end (0.5 + push) on, in the UP node.
  const double before = knee_at(**pushed, 0, 0.49), at = knee_at(**pushed, 0, 0.4999);
  EXPECT_LT(at, -0.05);
  EXPECT_GT(at, before);
  EXPECT_EQ(knee_at(**pushed, 1, 0.53), 0);
  EXPECT_EQ(knee_at(**pushed, 0, 0.02), 0);  // and before the dip begins
  EXPECT_LT(knee_at(**pushed, 0, 0.28), -0.45);  // its deepest a push later than without
}

TEST(HeadFeedbackTest, AfterAHeaderThatPassesToTheFootTheChestComesUpright) {
  // head_DOWN -> head_UP -> foot: in head_UP the next touch is the foot's, so no lean, while the
  // same ball in a header-to-header graph leans the chest.
  const std::string foot =
      "node { name: \"foot_down\" stage: DOWN contact_body: \"right_ankle\" contact_height: 0.5"
      " apex_height: 2.0 pose { leg_swing { side: RIGHT } } }\n"
      "node { name: \"foot_up\" stage: UP contact_body: \"right_ankle\" contact_height: 0.5"
      " apex_height: 2.0 pose { leg_swing { side: RIGHT } } }\n"
      "edge { from: \"foot_down\" to: \"foot_up\" }\n"
      "edge { from: \"foot_up\" to: \"head_DOWN\" }\n";
  std::string to_foot = HeaderGraph("head_feedback { lean_per_m: 2.5 redirect: 0 }");
  to_foot.replace(to_foot.find("edge { from: \"head_UP\" to: \"head_DOWN\" }"),
                  std::string("edge { from: \"head_UP\" to: \"head_DOWN\" }").size(),
                  "edge { from: \"head_UP\" to: \"foot_down\" }");
  for (const bool passes_to_foot : {false, true}) {
    SCOPED_TRACE(passes_to_foot);
    absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(
        passes_to_foot ? to_foot + foot
                       : HeaderGraph("head_feedback { lean_per_m: 2.5 redirect: 0 }"));
    ASSERT_TRUE(spec.ok()) << spec.status();
    AdaptiveWalk walk(&(*spec)->graph());
    JuggleEnv env(*spec, Rng(5));
    env.ResetAt(0, walk);
    mjData* d = env.data();
    // The ball rising 10 cm ahead of the target (as after a header), until head_UP.
    for (int i = 0; i < 200 && (*spec)->graph().node(env.node()).spec.stage() != config::UP;
         ++i) {
      double* ball = d->qpos + (*spec)->ball_qpos();
      ball[0] = d->qpos[0] + 0.18;
      ball[1] = d->qpos[1];
      ball[2] = 1.9;
      mju_zero(d->qvel + (*spec)->ball_dof(), 6);
      d->qvel[(*spec)->ball_dof() + 2] = 1.0;
      ASSERT_EQ(env.Step(kZeroAction, walk).outcome, Outcome::kRunning);
    }
    ASSERT_EQ((*spec)->graph().node(env.node()).spec.stage(), config::UP);
    env.Step(kZeroAction, walk);
    if (passes_to_foot) {
      EXPECT_EQ(env.state().swing_adjust.lean_pitch, 0);
    } else {
      EXPECT_LT(env.state().swing_adjust.lean_pitch, -0.1);
    }
  }
}

TEST(HeadFeedbackTest, WithTimingTheDipComesLaterForALateBallAndEarlierForAnEarlyOne) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> timed =
      SoccerSpecWithGraph(HeaderGraph("head_feedback { lean_per_m: 2.5 timing: 1 }"));
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> untimed =
      SoccerSpecWithGraph(HeaderGraph("head_feedback { lean_per_m: 2.5 }"));
  ASSERT_TRUE(timed.ok()) << timed.status();
  ASSERT_TRUE(untimed.ok()) << untimed.status();
  // The node's nominal contact is half a cycle (0.23 s) from the reset. Falling at 1 m/s from
  // 0.3 m above the contact height the ball crosses it after 0.17 s (early); thrown up at
  // 1 m/s from there, after 0.37 s (late).
  const Lean early = LeanFor(*timed, 0, 0, 0, 0, -1.0, 0.3);
  const Lean late = LeanFor(*timed, 0, 0, 0, 0, 1.0, 0.3);
  EXPECT_GT(early.adjust.head_phase, 0.05);  // the dip's pose evaluated later in it: earlier
  EXPECT_LT(late.adjust.head_phase, -0.05);
  EXPECT_EQ(LeanFor(*untimed, 0, 0, 0, 0, 1.0, 0.3).adjust.head_phase, 0);
  // For the late ball the knees are still bent at the node's nominal contact (φ = 0.5) and
  // straighten later; without the timing they are straight there.
  const int knee = (*timed)->joint(kRightKnee).qpos_adr;
  CharacterPose pose;
  ComputeReferencePose(**timed, 0, 0.4999, &pose, late.adjust);
  EXPECT_LT(pose[knee], -0.05);
  ComputeReferencePose(**timed, 0, 0.4999, &pose, SwingAdjust{});
  EXPECT_GT(pose[knee], -0.01);
}

TEST(HeadFeedbackTest, AHeadFeedbackOutsideAHeaderIsAConfigErrorNamingTheNodeAndField) {
  const std::string graph =
      "node { name: \"kick_down\" stage: DOWN initial: true contact_body: \"right_ankle\""
      " contact_height: 0.5 apex_height: 1.5 pose { leg_swing { side: RIGHT } }"
      " head_feedback { lean_per_m: 2 } }\n"
      "node { name: \"kick_up\" stage: UP contact_body: \"right_ankle\" contact_height: 0.5"
      " apex_height: 1.5 pose { leg_swing { side: RIGHT } } }\n"
      "edge { from: \"kick_down\" to: \"kick_up\" }\n"
      "edge { from: \"kick_up\" to: \"kick_down\" }\n";
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(graph);
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(spec.status().message().find("kick_down"), std::string::npos) << spec.status();
  EXPECT_NE(spec.status().message().find("head_feedback"), std::string::npos) << spec.status();
  EXPECT_NE(spec.status().message().find("head_dip"), std::string::npos) << spec.status();
}

}  // namespace
}  // namespace juggle::soccer_juggle
