// The planar toss-juggling model (configs/models/toss_arms.xml): the seed paper's PD gains
// (kp 1200, kd 70) at its 10 ms step hold the arms stably with the implicit-damping scheme,
// and balls fly ballistically through the arms without any contact.
#include <cmath>
#include <string>

#include <mujoco/mujoco.h>

#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"

namespace juggle::toss {
namespace {

class TossModelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char error[512] = "";
    m_ = mj_loadXML(testing::RepoPath("configs/models/toss_arms.xml").c_str(), nullptr, error,
                    sizeof(error));
    ASSERT_NE(m_, nullptr) << error;
    d_ = mj_makeData(m_);
  }
  void TearDown() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  int Joint(const char* name) { return mj_name2id(m_, mjOBJ_JOINT, name); }

  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
};

TEST_F(TossModelTest, HasSevenArmJointsAndSevenPlanarBalls) {
  for (const char* j : {"neck", "right_shoulder", "right_elbow", "right_wrist", "left_shoulder",
                        "left_elbow", "left_wrist"}) {
    EXPECT_GE(Joint(j), 0) << j;
  }
  for (int b = 0; b < 7; ++b) {
    EXPECT_GE(Joint(("ball" + std::to_string(b) + "_x").c_str()), 0);
  }
  EXPECT_EQ(m_->nv, 7 + 2 * 7);
  EXPECT_DOUBLE_EQ(m_->opt.timestep, 0.01);
}

TEST_F(TossModelTest, PaperGainsHoldAPoseStablyAtTenMilliseconds) {
  const double kp = 1200, h = m_->opt.timestep;
  const double target[3] = {0.4, -1.4, 0.3};  // shoulder, elbow, wrist of both arms
  const int arms[2][3] = {{Joint("right_shoulder"), Joint("right_elbow"), Joint("right_wrist")},
                          {Joint("left_shoulder"), Joint("left_elbow"), Joint("left_wrist")}};
  for (int step = 0; step < 200; ++step) {  // 2 s
    mju_zero(d_->qfrc_applied, m_->nv);
    for (const auto& arm : arms) {
      for (int k = 0; k < 3; ++k) {
        const int q = m_->jnt_qposadr[arm[k]], v = m_->jnt_dofadr[arm[k]];
        // Stable PD: kd is the joint damping (implicit in Euler); P on the predicted position.
        d_->qfrc_applied[v] = kp * (target[k] - d_->qpos[q] - h * d_->qvel[v]);
      }
    }
    mj_step(m_, d_);
    ASSERT_EQ(d_->warning[mjWARN_BADQACC].number, 0) << "diverged at step " << step;
  }
  for (const auto& arm : arms) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(d_->qpos[m_->jnt_qposadr[arm[k]]], target[k], 0.03);  // gravity sag only
      EXPECT_LT(std::abs(d_->qvel[m_->jnt_dofadr[arm[k]]]), 0.05);
    }
  }
}

TEST_F(TossModelTest, BallsFlyBallisticallyThroughTheArmsWithoutContacts) {
  const int x = m_->jnt_dofadr[Joint("ball0_x")], z = m_->jnt_dofadr[Joint("ball0_z")];
  d_->qvel[x] = -0.5;
  d_->qvel[z] = 3.0;
  const double x0 = d_->qpos[m_->jnt_qposadr[Joint("ball0_x")]];
  const double z0 = d_->qpos[m_->jnt_qposadr[Joint("ball0_z")]];
  const int steps = 60;  // 0.6 s, up and back down through the arms' space
  for (int i = 0; i < steps; ++i) {
    mj_step(m_, d_);
    ASSERT_EQ(d_->ncon, 0) << "a ball touched something at step " << i;
  }
  const double t = steps * m_->opt.timestep;
  EXPECT_NEAR(d_->qpos[m_->jnt_qposadr[Joint("ball0_x")]] - x0, -0.5 * t, 1e-9);
  // Euler's error on a parabola is g·h·t/2 ≈ 0.03 m here.
  EXPECT_NEAR(d_->qpos[m_->jnt_qposadr[Joint("ball0_z")]] - z0, 3.0 * t - 0.5 * 9.81 * t * t, 0.04);
}

}  // namespace
}  // namespace juggle::toss
