// The chest juggle's pose and feedback (ChestLean.steady, neck_pitch, dip; a chest node's
// head_feedback, BaseController::UpdateHeadLean and AddStanceBalance): the lean held, the knees
// dipping only during the fall, the chest swayed toward the coming ball by the legs, and the
// pose standing with zero action where the release's falls. Places are checked by MuJoCo's
// forward kinematics, not by the formulas' own numbers.
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
using testing::kChestPose;
using testing::SoccerSpecWithGraph;

// chest_DOWN <-> chest_UP with `pose` in the chest_lean and `extra` inside each node.
std::string ChestGraph(const std::string& extra, const std::string& pose = kChestPose) {
  std::string out;
  for (const char* stage : {"DOWN", "UP"}) {
    absl::StrAppend(&out, "node { name: \"chest_", stage, "\" stage: ", stage,
                    std::string(stage) == "DOWN" ? " initial: true" : "",
                    ChestNodeFields(pose), " ", extra, " }\n");
  }
  return out + "edge { from: \"chest_DOWN\" to: \"chest_UP\" }\n"
               "edge { from: \"chest_UP\" to: \"chest_DOWN\" }\n";
}

TEST(ChestPoseTest, ASteadyLeanHoldsTheChestWhileTheKneesDipOnlyDuringTheFall) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(ChestGraph(""));
  ASSERT_TRUE(spec.ok()) << spec.status();
  const int knee = (*spec)->joint(kRightKnee).qpos_adr;
  const int chest = (*spec)->joint(kChest).qpos_adr;
  auto pose_at = [&](int node, double phase) {
    CharacterPose pose;
    ComputeReferencePose(**spec, node, phase, &pose);
    return pose;
  };
  const CharacterPose contact = pose_at(0, 0.4999);
  for (const double phase : {0.0, 0.1, 0.25, 0.4}) {
    SCOPED_TRACE(phase);
    const CharacterPose pose = pose_at(0, phase);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(pose[chest + k], contact[chest + k], 1e-12);
    EXPECT_NEAR(pose[knee], -0.2 - 0.3 * std::sin(2 * M_PI * phase), 1e-12);
  }
  EXPECT_NEAR(pose_at(1, 0.7)[knee], -0.2, 1e-12);  // the UP node: no dip
  // The lean is back (the chest's sphere behind the root) and the neck takes the head back,
  // clear of a ball on the chest's top: the head's centre is more than the two radii
  // (0.1025 + 0.11 m) behind the chest's.
  MjDataPtr data(mj_makeData((*spec)->model()));
  std::copy(contact.begin(), contact.end(), data->qpos);
  mj_kinematics((*spec)->model(), data.get());
  const mjModel* m = (*spec)->model();
  const double* c = data->geom_xpos + 3 * mj_name2id(m, mjOBJ_GEOM, "chest");
  const double* h = data->geom_xpos + 3 * mj_name2id(m, mjOBJ_GEOM, "head");
  EXPECT_LT(c[0], contact[0]);
  EXPECT_LT(h[0], c[0] - 0.2125);

  // The release's chest_lean is what it was: the lean swings with sin(πφ), the knees stay.
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> release =
      SoccerSpecWithGraph(ChestGraph("", ""));
  ASSERT_TRUE(release.ok()) << release.status();
  CharacterPose a, b;
  ComputeReferencePose(**release, 0, 0.1, &a);
  ComputeReferencePose(**release, 0, 0.4, &b);
  EXPECT_EQ(a[knee], -0.46);
  EXPECT_EQ(b[knee], -0.46);
  EXPECT_GT(std::abs(a[chest] - b[chest]), 0.01);
}

// The chest's sphere relative to the midpoint between the ankles (world x, y) when a ball put
// `ahead`, `left` of the target, falling from rest 0.8 m above the contact height, comes down
// to it: zero action, the ball's flight set by hand each step (it never touches).
std::array<double, 2> ChestAtTheCrossing(const std::shared_ptr<const JuggleSpec>& spec,
                                         double ahead, double left) {
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(3));
  env.ResetAt(0, walk);
  mjData* d = env.data();
  const mjModel* m = spec->model();
  const double g = spec->env().gravity();
  const double x = d->qpos[0] - 0.09 + ahead, y = d->qpos[1] + left;
  const int steps = static_cast<int>(std::sqrt(2 * 0.8 / g) / spec->control_dt());
  for (int i = 0; i < steps; ++i) {
    const double t = i * spec->control_dt();
    double* ball = d->qpos + spec->ball_qpos();
    double* v = d->qvel + spec->ball_dof();
    ball[0] = x;
    ball[1] = y;
    ball[2] = 1.41 + 0.8 - 0.5 * g * t * t;
    mju_zero(v, 6);
    v[2] = -g * t;
    EXPECT_EQ(env.Step(kZeroAction, walk).outcome, Outcome::kRunning);
  }
  const double* c = d->geom_xpos + 3 * mj_name2id(m, mjOBJ_GEOM, "chest");
  const double* r = d->xpos + 3 * mj_name2id(m, mjOBJ_BODY, "right_ankle");
  const double* l = d->xpos + 3 * mj_name2id(m, mjOBJ_BODY, "left_ankle");
  return {c[0] - (r[0] + l[0]) / 2, c[1] - (r[1] + l[1]) / 2};
}

TEST(ChestFeedbackTest, TheLegsSwayTheChestTowardABallComingDownAheadAndToTheLeft) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(
      ChestGraph("head_feedback { lean_per_m: 3 redirect: 0 contact_radius_m: 0.22 }"));
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> plain = SoccerSpecWithGraph(ChestGraph(""));
  ASSERT_TRUE(spec.ok()) << spec.status();
  ASSERT_TRUE(plain.ok()) << plain.status();
  const std::array<double, 2> swayed = ChestAtTheCrossing(*spec, 0.04, 0.05);
  const std::array<double, 2> still = ChestAtTheCrossing(*plain, 0.04, 0.05);
  EXPECT_GT(swayed[0] - still[0], 0.01);
  EXPECT_GT(swayed[1] - still[1], 0.02);
  // The other way round on the other side.
  const std::array<double, 2> back_right = ChestAtTheCrossing(*spec, -0.04, -0.05);
  const std::array<double, 2> still_back_right = ChestAtTheCrossing(*plain, -0.04, -0.05);
  EXPECT_LT(back_right[0] - still_back_right[0], -0.01);
  EXPECT_LT(back_right[1] - still_back_right[1], -0.02);
}

// The character of `spec` with zero action and the ball out of play (40 m up, at rest): the
// seconds it stands, up to `seconds`.
double StandWithoutBall(const std::shared_ptr<const JuggleSpec>& spec, double seconds) {
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(11));
  env.ResetAt(0, walk);
  mjData* d = env.data();
  const int steps = static_cast<int>(std::round(seconds / spec->control_dt()));
  for (int i = 0; i < steps; ++i) {
    double* ball = d->qpos + spec->ball_qpos();
    ball[0] = d->qpos[0];
    ball[1] = d->qpos[1];
    ball[2] = 40.0;
    mju_zero(d->qvel + spec->ball_dof(), 6);
    if (env.Step(kZeroAction, walk).outcome != Outcome::kRunning) {
      return (i + 1) * spec->control_dt();
    }
  }
  return seconds;
}

TEST(ChestPoseTest, TheChestPoseStandsWithZeroActionWhereTheReleasesKneeBendFalls) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> chest =
      SoccerSpecWithGraph(ChestGraph("", "hold: true chest_amplitude: 0.7 neck_pitch: 0.6 "
                                         "knee: 0.2 ankle_amplitude: 0.2"));
  ASSERT_TRUE(chest.ok()) << chest.status();
  EXPECT_EQ(StandWithoutBall(*chest, 10.0), 10.0);
  // The release's knees (0.46 rad) under the same lean fall within two seconds.
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> release =
      SoccerSpecWithGraph(ChestGraph("", "hold: true chest_amplitude: 0.7 neck_pitch: 0.6"));
  ASSERT_TRUE(release.ok()) << release.status();
  EXPECT_LT(StandWithoutBall(*release, 10.0), 2.0);
}

TEST(ChestFeedbackTest, AHeadFeedbackOnALegSwingIsAConfigErrorNamingTheNode) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(
      "node { name: \"foot_down\" stage: DOWN initial: true contact_body: \"right_ankle\""
      " contact_height: 0.5 apex_height: 1.4 pose { leg_swing { side: RIGHT } }"
      " head_feedback { lean_per_m: 2 } }\n"
      "node { name: \"foot_up\" stage: UP contact_body: \"right_ankle\" contact_height: 0.5"
      " apex_height: 1.4 pose { leg_swing { side: RIGHT } } }\n"
      "edge { from: \"foot_down\" to: \"foot_up\" }\n"
      "edge { from: \"foot_up\" to: \"foot_down\" }\n");
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("node 'foot_down'"));
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("head_feedback"));
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("chest_lean"));
}

}  // namespace
}  // namespace juggle::soccer_juggle
