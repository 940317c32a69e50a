// env.stance_change's pieces (envs/soccer_juggle/stance_change.h): which nodes change the
// standing foot, where the kicking foot is put down — checked by forward kinematics of the
// angles it returns — and the balance targets' lean. The zero-action behaviour they add up to
// is in stance_test.cc.
#include "envs/soccer_juggle/stance_change.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "absl/strings/str_cat.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/base_controller.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

int Node(const JuggleSpec& spec, const char* name) { return *spec.graph().FindNode(name); }

CursorState At(const JuggleSpec& spec, const char* current, const char* next) {
  CursorState cursor;
  cursor.current = Node(spec, current);
  cursor.next = Node(spec, next);
  return cursor;
}

TEST(StanceChangeTest, OnlyAKickBeforeTheOtherFootsHandsTheStanceOver) {
  std::shared_ptr<const JuggleSpec> spec = testing::LoadSpec("both_feet_planner");
  ASSERT_NE(spec, nullptr);
  const ControlGraph& g = spec->graph();
  EXPECT_TRUE(HandsStanceOver(g, At(*spec, "right_foot_up", "left_foot_down")));
  EXPECT_TRUE(HandsStanceOver(g, At(*spec, "left_foot_up", "right_foot_down")));
  EXPECT_FALSE(HandsStanceOver(g, At(*spec, "right_foot_up", "right_foot_down")));
  EXPECT_FALSE(HandsStanceOver(g, At(*spec, "right_foot_down", "right_foot_up")));
  bool left = true;
  EXPECT_FALSE(KickFollowsBothFeet(g, At(*spec, "right_foot_up", "left_foot_down"), &left));
}

TEST(StanceChangeTest, AHeaderBeforeAKickNamesTheKicksSide) {
  std::shared_ptr<const JuggleSpec> spec = testing::LoadSpec("foot_and_head_planner");
  ASSERT_NE(spec, nullptr);
  const ControlGraph& g = spec->graph();
  bool left = true;
  EXPECT_TRUE(KickFollowsBothFeet(g, At(*spec, "head_up", "right_foot_down"), &left));
  EXPECT_FALSE(left);
  EXPECT_FALSE(KickFollowsBothFeet(g, At(*spec, "head_down", "head_up"), &left));
  EXPECT_FALSE(KickFollowsBothFeet(g, At(*spec, "head_up", "head_down"), &left));
  // A kick up to the head is not a change of feet: both stand next.
  EXPECT_FALSE(HandsStanceOver(g, At(*spec, "right_foot_up", "head_down")));
}

TEST(StanceChangeTest, LeanAndHeaderShiftGrowOverTheFollowThroughOnly) {
  config::StanceChange change;
  change.set_lean(0.08);
  change.set_header_shift(1.0);
  EXPECT_EQ(LeanTowardKick(change, false, 0.3), 0.0);
  EXPECT_NEAR(LeanTowardKick(change, false, 0.75), -0.04, 1e-12);  // right kick: toward −y
  EXPECT_NEAR(LeanTowardKick(change, true, 1.0), 0.08, 1e-12);
  EXPECT_EQ(HeaderShiftShare(change, 0.5), 0.0);
  EXPECT_NEAR(HeaderShiftShare(change, 0.75), 0.5, 1e-12);
}

// The quaternion of ball joint `j` in `pose`.
std::array<double, 4> Quat(const JuggleSpec& spec, const CharacterPose& pose, JointId j) {
  const double* q = pose.data() + spec.joint(j).qpos_adr;
  return {q[0], q[1], q[2], q[3]};
}

TEST(StanceChangeTest, AHeaderBeforeAKickRollsTheStandingLegIntoTheKicksFirstPose) {
  const std::string run = testing::WriteTemp(
      "run.textproto",
      absl::StrCat("base_config: \"",
                   testing::RepoPath("configs/foot_and_head_planner.textproto"),
                   "\"\nname: \"t\"\n",
                   "soccer_juggle { env { stance_change { header_roll: 1 } } }\n"));
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(run);
  ASSERT_TRUE(config.ok()) << config.status();
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> created = JuggleSpec::Create(*config);
  ASSERT_TRUE(created.ok()) << created.status();
  const JuggleSpec& spec = **created;
  const BaseController base(spec);
  MjDataPtr data(mj_makeData(spec.model()));
  const double roll = spec.graph().node(Node(spec, "right_foot_down")).spec.pose().leg_swing()
                          .stance_roll();
  ASSERT_GT(roll, 0.05);  // the kick's pose rolls its standing leg: the test means something

  CursorState cursor = At(spec, "head_up", "right_foot_down");
  SwingAdjust adjust;
  for (const double phase : {0.3, 0.5, 0.75, 1.0}) {
    cursor.phase = phase;
    base.UpdateSwingAdjust(*data, cursor, false, &adjust);
    EXPECT_NEAR(adjust.stance_roll, std::max(0.0, 2 * (phase - 0.5)) * roll, 1e-12) << phase;
    EXPECT_FALSE(adjust.stance_roll_left_kick);
  }
  // At the node's end the standing leg is where the kick's node starts: no step in the pose.
  CharacterPose header_end, kick_start, standing;
  ComputeReferencePose(spec, Node(spec, "head_up"), 1.0, &header_end, adjust);
  ComputeReferencePose(spec, Node(spec, "right_foot_down"), 0.0, &kick_start);
  ComputeReferencePose(spec, Node(spec, "head_up"), 1.0, &standing);
  for (const JointId j : {kLeftHip, kLeftAnkle}) {
    const std::array<double, 4> a = Quat(spec, header_end, j), b = Quat(spec, kick_start, j);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(a[k], b[k], 1e-12) << j;
    EXPECT_GT(RotationSin2(a.data(), Quat(spec, standing, j).data()), 1e-4) << j;
  }
  // Before another header the legs stay as they were.
  cursor = At(spec, "head_up", "head_down");
  cursor.phase = 1.0;
  base.UpdateSwingAdjust(*data, cursor, false, &adjust);
  EXPECT_EQ(adjust.stance_roll, 0.0);
  // Without header_roll (the shipped config) nothing changes.
  std::shared_ptr<const JuggleSpec> shipped = testing::LoadSpec("full_planner");
  ASSERT_NE(shipped, nullptr);
  ASSERT_EQ(shipped->env().stance_change().header_roll(), 0.0);
  const BaseController shipped_base(*shipped);
  CursorState before_kick;
  before_kick.current = Node(*shipped, "head_up");
  before_kick.next = Node(*shipped, "right_foot_down");
  before_kick.phase = 1.0;
  shipped_base.UpdateSwingAdjust(*data, before_kick, false, &adjust);
  EXPECT_EQ(adjust.stance_roll, 0.0);
}

// Forward kinematics of the placed leg: the hip at the angles PlaceKickingFoot returns, the
// knee straight. The ankle must come down where the function aimed it: at the centre of mass's
// capture point moved place_width to the kicking side.
void ExpectFootLandsAtTheCapturePoint(bool kick_left) {
  std::shared_ptr<const JuggleSpec> spec = testing::LoadSpec("both_feet_planner");
  ASSERT_NE(spec, nullptr);
  const mjModel* m = spec->model();
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(3));
  env.ResetAt(Node(*spec, kick_left ? "left_foot_down" : "right_foot_down"), walk);
  mjData* d = env.data();
  // A pelvis tilted forward and sideways, moving: the placement has to account for both.
  double tilt[4];
  const double axis[3] = {0.6, 0, 0.8};
  mju_axisAngle2Quat(tilt, axis, 0.08);
  double tilted[4];
  mju_mulQuat(tilted, d->qpos + 3, tilt);
  mju_copy4(d->qpos + 3, tilted);
  d->qvel[0] = 0.5;
  d->qvel[1] = kick_left ? 0.2 : -0.2;
  mj_kinematics(m, d);
  mj_comPos(m, d);

  SwingAdjust adjust;
  PlaceKickingFoot(*spec, *d, kick_left, &adjust);
  const config::StanceChange& change = spec->env().stance_change();
  const double* com = d->subtree_com + 3 * spec->root_body();
  const double target_x = com[0] + change.capture_s() * d->qvel[0];
  const double target_y = com[1] + change.capture_s() * d->qvel[1] +
                          (kick_left ? 1 : -1) * change.place_width();

  const ActuatedJoint& hip = spec->joint(kick_left ? kLeftHip : kRightHip);
  const ActuatedJoint& knee = spec->joint(kick_left ? kLeftKnee : kRightKnee);
  const ActuatedJoint& ankle = spec->joint(kick_left ? kLeftAnkle : kRightAnkle);
  const int foot = m->dof_bodyid[ankle.dof_adr];
  const double before[2] = {d->xpos[3 * foot], d->xpos[3 * foot + 1]};
  // Outward abduction is about −x for the right leg, +x for the left (reference_pose.cc).
  const double rotvec[3] = {(kick_left ? 1 : -1) * adjust.place_abduction, 0, adjust.place_hip};
  const double angle = mju_norm3(rotvec);
  double unit[3];
  mju_scl3(unit, rotvec, 1 / angle);
  mju_axisAngle2Quat(d->qpos + hip.qpos_adr, unit, angle);
  d->qpos[knee.qpos_adr] = 0;
  mj_kinematics(m, d);
  const double* placed = d->xpos + 3 * foot;  // the ankle joint's position
  // The test means something: the foot moves well away from where it stood.
  EXPECT_GT(std::hypot(placed[0] - before[0], placed[1] - before[1]), 0.05);
  EXPECT_NEAR(placed[0], target_x, 0.02);
  EXPECT_NEAR(placed[1], target_y, 0.02);
}

TEST(StanceChangeTest, RightFootIsPutDownAtTheCapturePointMovedToItsSide) {
  ExpectFootLandsAtTheCapturePoint(false);
}

TEST(StanceChangeTest, LeftFootIsPutDownAtTheCapturePointMovedToItsSide) {
  ExpectFootLandsAtTheCapturePoint(true);
}

}  // namespace
}  // namespace juggle::soccer_juggle
