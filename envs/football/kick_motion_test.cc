// The scripted kick's reference pose (envs/football/kick_motion.h): without a knee lag the knee
// opens with the hip over the forward swing; with one it stays folded for that share of the
// swing, then opens to the same forward angle (the planner's knee change included) by its end,
// and the hip's path is the same either way. A step into the kick (KickMotion.step), checked by
// MuJoCo's forward kinematics of the reference pose with the root held where it stands: the
// pelvis first moves over the right foot, the left foot rises at mid-swing and comes down the
// step's length ahead with both soles level, and the back-swing brings the left leg straight.
#include "envs/football/kick_motion.h"

#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "envs/football/spec.h"
#include "envs/mujoco_model.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::football {
namespace {

using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;

// The shipped kick config with the given fields of `motion` set.
std::shared_ptr<const FootballSpec> SpecWithMotion(const std::string& name,
                                                   const std::string& motion) {
  const std::string text =
      absl::StrCat("base_config: \"", RepoPath("configs/football_kick.textproto"), "\"\nname: \"",
                   name, "\"\nfootball { motion { ", motion, " } }\n");
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(WriteTemp(name + ".textproto", text));
  EXPECT_TRUE(config.ok()) << config.status();
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  if (!spec.ok()) return nullptr;
  return std::static_pointer_cast<const FootballSpec>(*spec);
}

constexpr char kMotion[] =
    "start_s: 0.2 backswing_s: 0.3 swing_s: 0.2 hip_forward: 1.7 knee_back: 1.5 knee_forward: 0";

struct LegAt {
  double knee;
  double hip_quat[4];
};

LegAt ReferenceAt(const FootballSpec& spec, double t, const KickAdjust& adjust) {
  CharacterPose pose;
  KickReferencePose(spec, t, adjust, &pose);
  const humanoid::Joints& joints = spec.joints();
  LegAt leg;
  leg.knee = pose[joints[humanoid::kRightKnee].qpos_adr];
  for (int k = 0; k < 4; ++k) leg.hip_quat[k] = pose[joints[humanoid::kRightHip].qpos_adr + k];
  return leg;
}

TEST(KickMotionTest, AKneeLagHoldsTheKneeFoldedThenOpensItByTheSwingsEndOnTheSameHipPath) {
  std::shared_ptr<const FootballSpec> together =
      SpecWithMotion("kick_together", absl::StrCat(kMotion, " knee_lag: 0"));
  std::shared_ptr<const FootballSpec> whip =
      SpecWithMotion("kick_whip", absl::StrCat(kMotion, " knee_lag: 0.5"));
  ASSERT_NE(together, nullptr);
  ASSERT_NE(whip, nullptr);
  KickAdjust adjust;
  adjust.knee = 0.1;
  const double swing = 0.2 + 0.3, recover = swing + 0.2;

  // Without a lag the knee has opened a quarter of the swing in; with one it is still folded.
  EXPECT_GT(ReferenceAt(*together, swing + 0.05, adjust).knee, -1.5 + 0.1);
  for (double u : {0.0, 0.1, 0.25, 0.45}) {
    EXPECT_DOUBLE_EQ(ReferenceAt(*whip, swing + u * 0.2, adjust).knee, -1.5) << "u " << u;
  }
  // After the lag it opens monotonically to the forward angle with the planner's change.
  double previous = -1.5;
  for (double u : {0.6, 0.7, 0.8, 0.9, 0.999}) {
    const double knee = ReferenceAt(*whip, swing + u * 0.2, adjust).knee;
    EXPECT_GT(knee, previous) << "u " << u;
    previous = knee;
  }
  EXPECT_NEAR(ReferenceAt(*whip, recover - 1e-9, adjust).knee, -(0 + 0.1), 1e-6);
  EXPECT_NEAR(ReferenceAt(*together, recover - 1e-9, adjust).knee, -(0 + 0.1), 1e-6);

  // The lag moves the knee only: the hip, the back-swing and the recovery are the same.
  for (double t = 0.15; t < 1.3; t += 0.01) {
    const LegAt a = ReferenceAt(*together, t, adjust);
    const LegAt b = ReferenceAt(*whip, t, adjust);
    for (int k = 0; k < 4; ++k) EXPECT_DOUBLE_EQ(a.hip_quat[k], b.hip_quat[k]) << "t " << t;
    if (t < swing || t >= recover) {
      EXPECT_DOUBLE_EQ(a.knee, b.knee) << "t " << t;
    }
  }
}

// Where a pose puts the ankles' joints (world, m) and how far each sole tilts from level (the
// angle between its up axis and the root's, rad), the root held at the standing pose's.
struct Feet {
  double left[3], right[3];
  double left_tilt, right_tilt;
};

Feet FeetOf(const FootballSpec& spec, const CharacterPose& pose) {
  const mjModel* m = spec.model();
  MjDataPtr d(mj_makeData(m));
  mju_copy(d->qpos, pose.data(), humanoid::kCharacterNq);
  mj_kinematics(m, d.get());
  Feet feet;
  const int root = spec.root_body();
  auto tilt = [&](int body) {
    // The local y axis is up at rest (configs/models/humanoid.xml); column 1 of xmat.
    double dot = 0;
    for (int r = 0; r < 3; ++r)
      dot += d->xmat[9 * body + 3 * r + 1] * d->xmat[9 * root + 3 * r + 1];
    return std::acos(std::min(1.0, dot));
  };
  const int left = mj_name2id(m, mjOBJ_BODY, "left_ankle");
  const int right = mj_name2id(m, mjOBJ_BODY, "right_ankle");
  mju_copy3(feet.left, d->xpos + 3 * left);
  mju_copy3(feet.right, d->xpos + 3 * right);
  feet.left_tilt = tilt(left);
  feet.right_tilt = tilt(right);
  return feet;
}

Feet FeetAt(const FootballSpec& spec, double t) {
  CharacterPose pose;
  KickReferencePose(spec, t, {}, &pose);
  return FeetOf(spec, pose);
}

TEST(KickMotionTest, AStepMovesThePelvisOverTheRightFootThenPutsTheLeftFootDownItsLengthAhead) {
  constexpr double kLength = 0.3;
  std::shared_ptr<const FootballSpec> spec = SpecWithMotion(
      "kick_step", absl::StrCat(kMotion, " step { length_m: 0.3 shift_s: 0.25 swing_s: 0.3 }"));
  ASSERT_NE(spec, nullptr);
  const KickTimes times = KickTimesOf(spec->football().motion(), {});
  EXPECT_DOUBLE_EQ(times.step, 0.2);
  EXPECT_DOUBLE_EQ(times.step_swing, 0.45);
  EXPECT_DOUBLE_EQ(times.start, 0.75);
  EXPECT_DOUBLE_EQ(times.swing, 1.05);
  const Feet standing = FeetAt(*spec, 0.1);
  const double half_width = standing.left[1];
  EXPECT_NEAR(half_width, spec->hip_half_width_m(), 1e-3);

  // End of the shift: the feet lie a half width to the left of where they stood, relative to
  // the root: the pelvis is over the right foot. Soles level; no foot has moved ahead.
  const Feet shifted = FeetAt(*spec, times.step_swing);
  EXPECT_NEAR(shifted.right[1], standing.right[1] + half_width, 2e-3);
  EXPECT_NEAR(shifted.left[1], standing.left[1] + half_width, 2e-3);
  EXPECT_NEAR(shifted.left[0], standing.left[0], 1e-3);
  EXPECT_LT(shifted.left_tilt, 1e-3);
  EXPECT_LT(shifted.right_tilt, 1e-3);

  // Mid-swing: the left foot is off the floor by a few centimetres.
  const Feet mid = FeetAt(*spec, 0.5 * (times.step_swing + times.start));
  EXPECT_GT(mid.left[2] - mid.right[2], 0.03);

  // The plant: the left foot the step's length ahead of the right, level with it, both soles
  // level, across as after the shift.
  const Feet planted = FeetAt(*spec, times.start - 1e-9);
  EXPECT_NEAR(planted.left[0] - planted.right[0], kLength, 2e-3);
  EXPECT_NEAR(planted.left[2], planted.right[2], 2e-3);
  EXPECT_NEAR(planted.left[1] - planted.right[1], 2 * half_width, 2e-3);
  EXPECT_LT(planted.left_tilt, 1e-3);
  EXPECT_LT(planted.right_tilt, 1e-3);

  // The back-swing straightens the left leg under the pelvis (its standing place).
  const Feet back = FeetAt(*spec, times.swing);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.left[c], standing.left[c], 1e-6) << c;
  EXPECT_NEAR(StepComAhead(spec->football().motion(), times, times.start - 1e-9), kLength / 2,
              1e-6);
  EXPECT_DOUBLE_EQ(StepComAhead(spec->football().motion(), times, times.step_swing), 0);
}

TEST(KickMotionTest, WithoutAStepTheKickStartsAtStartSAndTheLeftLegStands) {
  std::shared_ptr<const FootballSpec> spec = SpecWithMotion("kick_no_step", kMotion);
  ASSERT_NE(spec, nullptr);
  KickAdjust adjust;
  adjust.timing_s = 0.05;
  const KickTimes times = KickTimesOf(spec->football().motion(), adjust);
  EXPECT_DOUBLE_EQ(times.step, 0.15);
  EXPECT_DOUBLE_EQ(times.step_swing, 0.15);
  EXPECT_DOUBLE_EQ(times.start, 0.15);
  const Feet standing = FeetAt(*spec, 0);
  for (double t = 0; t < 1.5; t += 0.05) {
    const Feet feet = FeetAt(*spec, t);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(feet.left[c], standing.left[c]) << "t " << t;
  }
}

TEST(KickMotionTest, AStepIsAConfigErrorOutsideTheKickTask) {
  const std::string text = absl::StrCat(
      "base_config: \"", RepoPath("configs/football_trap_kick.textproto"),
      "\"\nname: \"trap_kick_step\"\nfootball { motion { step { length_m: 0.3 } } }\n");
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(WriteTemp("trap_kick_step.textproto", text));
  ASSERT_TRUE(config.ok()) << config.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  ASSERT_FALSE(spec.ok());
  EXPECT_EQ(spec.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(spec.status().message().find("step"), std::string::npos) << spec.status();
  EXPECT_NE(spec.status().message().find("length_m"), std::string::npos) << spec.status();
  EXPECT_NE(spec.status().message().find("TRAP_KICK"), std::string::npos) << spec.status();
}

}  // namespace
}  // namespace juggle::football
