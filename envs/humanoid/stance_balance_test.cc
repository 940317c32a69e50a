// The stance balance's torques (envs/humanoid/stance_balance.h) on a hand-made state: the
// centre-of-mass term through the stance ankle, and hip_roll / hip_pitch putting that term's
// roll (about the world's forward axis) / pitch (about its left axis) on the pelvis through the
// stance hip — read back in the world frame from each joint's body frame, an independent path
// from the one the code writes them by — and the yaw term's two headings, the world's and the
// stance foot's, on a character turned and a hip twisted by hand.
#include "envs/humanoid/stance_balance.h"

#include <array>
#include <string>

#include "envs/mujoco_model.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::humanoid {
namespace {

class StanceBalanceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<MjModelPtr> model =
        LoadModelXml(juggle::testing::RepoPath("configs/models/juggle_scene.xml"), "test");
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = *std::move(model);
    absl::StatusOr<Joints> joints = ResolveJoints(model_.get());
    ASSERT_TRUE(joints.ok()) << joints.status();
    joints_ = *joints;
    data_.reset(mj_makeData(model_.get()));
    root_ = mj_name2id(model_.get(), mjOBJ_BODY, "root");
    ASSERT_GE(root_, 0);
    mj_forward(model_.get(), data_.get());
  }

  // The feed-forward of `gains` standing on the left foot.
  std::array<double, kCharacterNv> Torques(const config::StanceBalance& gains) {
    std::array<double, kCharacterNv> tau{};
    AddStanceBalance(joints_, gains, Foot::kLeft, root_, 100.0, model_.get(), data_.get(),
                     tau.data());
    return tau;
  }

  // Only the centre-of-mass term (kp 830), its target 3 cm to the left of and 2 cm behind
  // where the centre of mass is over the left ankle: the ankle's world torque is then
  // (830 · 0.03, −830 · 0.02, 0).
  void OffsetTarget(config::StanceBalance* gains) {
    gains->set_com_kp(830);
    gains->set_com_kd(0);
    const double* com = data_->subtree_com + 3 * root_;
    const double* ankle = data_->xpos + 3 * model_->dof_bodyid[joints_[kLeftAnkle].dof_adr];
    gains->set_com_x(com[0] - ankle[0] + 0.02);
    gains->set_com_y(com[1] - ankle[1] + 0.03);
  }

  // `joint`'s three torques in `tau`, from its body's frame into the world's.
  std::array<double, 3> InWorld(const std::array<double, kCharacterNv>& tau, JointId joint) {
    const int dof = joints_[joint].dof_adr;
    std::array<double, 3> world{};
    const double* r = data_->xmat + 9 * model_->dof_bodyid[dof];  // body to world, row-major
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) world[i] += r[3 * i + k] * tau[dof + k];
    }
    return world;
  }

  MjModelPtr model_;
  MjDataPtr data_;
  Joints joints_;
  int root_ = -1;
};

TEST_F(StanceBalanceTest, TheHipRollPutsTheAnklesRollOnThePelvisThroughTheStanceHip) {
  config::StanceBalance gains;
  OffsetTarget(&gains);

  const std::array<double, kCharacterNv> alone = Torques(gains);
  // The ankle alone: the world torque (−kp·e_y, kp·e_x, 0) for e = (−0.02, −0.03).
  const std::array<double, 3> on_foot = InWorld(alone, kLeftAnkle);
  EXPECT_NEAR(on_foot[0], 830 * 0.03, 1e-9);
  EXPECT_NEAR(on_foot[1], -830 * 0.02, 1e-9);
  EXPECT_NEAR(on_foot[2], 0, 1e-9);
  for (double t : InWorld(alone, kLeftHip)) EXPECT_EQ(t, 0);

  gains.set_hip_roll(1.5);
  const std::array<double, kCharacterNv> with = Torques(gains);
  // The ankle unchanged; on the thigh −1.5 × the foot's roll, so the pelvis gets +1.5 × it.
  EXPECT_EQ(InWorld(with, kLeftAnkle), on_foot);
  const std::array<double, 3> on_thigh = InWorld(with, kLeftHip);
  EXPECT_NEAR(on_thigh[0], -1.5 * on_foot[0], 1e-9);
  EXPECT_NEAR(on_thigh[1], 0, 1e-9);
  EXPECT_NEAR(on_thigh[2], 0, 1e-9);
  // Nothing else moves, the swing leg's hip included.
  for (int dof = 0; dof < kCharacterNv; ++dof) {
    const int left_hip = joints_[kLeftHip].dof_adr;
    if (dof >= left_hip && dof < left_hip + 3) continue;
    EXPECT_EQ(with[dof], alone[dof]) << "dof " << dof;
  }
}

TEST_F(StanceBalanceTest, TheHipPitchPutsTheAnklesPitchOnThePelvisThroughTheStanceHip) {
  config::StanceBalance gains;
  OffsetTarget(&gains);
  const std::array<double, 3> on_foot = InWorld(Torques(gains), kLeftAnkle);
  ASSERT_NEAR(on_foot[1], -830 * 0.02, 1e-9);

  gains.set_hip_pitch(0.5);
  const std::array<double, kCharacterNv> pitch = Torques(gains);
  EXPECT_EQ(InWorld(pitch, kLeftAnkle), on_foot);
  const std::array<double, 3> on_thigh = InWorld(pitch, kLeftHip);
  EXPECT_NEAR(on_thigh[0], 0, 1e-9);  // no roll without hip_roll
  EXPECT_NEAR(on_thigh[1], -0.5 * on_foot[1], 1e-9);
  EXPECT_NEAR(on_thigh[2], 0, 1e-9);

  gains.set_hip_roll(1.5);  // both: each axis its own share
  const std::array<double, 3> both = InWorld(Torques(gains), kLeftHip);
  EXPECT_NEAR(both[0], -1.5 * on_foot[0], 1e-9);
  EXPECT_NEAR(both[1], -0.5 * on_foot[1], 1e-9);
}

// Turns the character (root) by `root_yaw` about the world's vertical and twists the left hip by
// `hip_twist` about the thigh's long axis (the leg hangs straight, so that is the vertical too),
// zero velocities, and recomputes the kinematics.
void Turn(const mjModel* m, mjData* d, const Joints& joints, double root_yaw, double hip_twist) {
  const double up[3] = {0, 0, 1}, along_thigh[3] = {0, 1, 0};
  double turn[4], hip[4];
  mju_axisAngle2Quat(turn, up, root_yaw);
  mju_mulQuat(d->qpos + 3, turn, kUprightRoot);
  mju_axisAngle2Quat(hip, along_thigh, hip_twist);
  mju_copy4(d->qpos + joints[kLeftHip].qpos_adr, hip);
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);
}

TEST_F(StanceBalanceTest, TheYawTermHoldsTheWorldsHeadingUnlessToldToHoldTheStanceFoots) {
  config::StanceBalance gains;
  gains.set_yaw_kp(300);
  const int yaw_dof = joints_[kLeftHip].dof_adr + 1;  // about the thigh's (and root's) vertical

  // The whole character turned 0.2 rad, the legs straight: the world's target pulls it back,
  // the stance foot's sees nothing to correct.
  Turn(model_.get(), data_.get(), joints_, 0.2, 0);
  EXPECT_NEAR(Torques(gains)[yaw_dof], 300 * 0.2, 1e-9);
  gains.set_yaw_from_stance_foot(true);
  EXPECT_NEAR(Torques(gains)[yaw_dof], 0, 1e-9);

  // Root square to the world, the stance foot turned 0.1 rad left by its hip: now only the
  // stance foot's target acts, turning the pelvis after the foot (a torque to the left on the
  // pelvis is −0.1·kp on the thigh's dof, which the pelvis feels as its reaction).
  Turn(model_.get(), data_.get(), joints_, 0, 0.1);
  EXPECT_NEAR(Heading(data_->xmat + 9 * model_->dof_bodyid[joints_[kLeftAnkle].dof_adr]), 0.1,
              1e-9);
  EXPECT_NEAR(Torques(gains)[yaw_dof], -300 * 0.1, 1e-9);
  gains.set_yaw_from_stance_foot(false);
  EXPECT_NEAR(Torques(gains)[yaw_dof], 0, 1e-9);

  // Both at once, across the ±π seam: the difference is taken on the circle.
  gains.set_yaw_from_stance_foot(true);
  Turn(model_.get(), data_.get(), joints_, M_PI - 0.05, 0.1);
  EXPECT_NEAR(Torques(gains)[yaw_dof], -300 * 0.1, 1e-9);
}

}  // namespace
}  // namespace juggle::humanoid
