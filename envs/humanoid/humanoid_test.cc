// The humanoid's joints and stable PD (envs/humanoid/humanoid.h): resolved alike in every scene
// that includes it, refused by name when a joint is missing, and the PD torque of a known pose
// error equal to the one written out by hand (an axis-angle from the rotation, not mju_subQuat).
#include "envs/humanoid/humanoid.h"

#include <cmath>
#include <string>
#include <vector>

#include "envs/mujoco_model.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::humanoid {
namespace {

using ::testing::HasSubstr;

MjModelPtr Load(const std::string& scene) {
  absl::StatusOr<MjModelPtr> m =
      LoadModelXml(juggle::testing::RepoPath("configs/models/" + scene), "test");
  EXPECT_TRUE(m.ok()) << m.status();
  return m.ok() ? *std::move(m) : nullptr;
}

TEST(HumanoidTest, TheJointsResolveAlikeInTheJugglingSceneAndOnThePitch) {
  MjModelPtr juggling = Load("juggle_scene.xml"), pitch = Load("football_pitch.xml");
  ASSERT_NE(juggling, nullptr);
  ASSERT_NE(pitch, nullptr);
  absl::StatusOr<Joints> a = ResolveJoints(juggling.get()), b = ResolveJoints(pitch.get());
  ASSERT_TRUE(a.ok()) << a.status();
  ASSERT_TRUE(b.ok()) << b.status();
  int dofs = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    SCOPED_TRACE(kJointNames[j]);
    EXPECT_EQ((*a)[j].qpos_adr, (*b)[j].qpos_adr);
    EXPECT_EQ((*a)[j].dof_adr, (*b)[j].dof_adr);
    EXPECT_EQ((*a)[j].dofs, (*b)[j].dofs);
    EXPECT_EQ((*a)[j].kp, DefaultGainsFor(static_cast<JointId>(j)).kp);
    dofs += (*a)[j].dofs;
  }
  EXPECT_EQ(dofs, kNumActuatedDofs);
  EXPECT_EQ(JointIdByName("left_knee"), kLeftKnee);
  EXPECT_EQ(JointIdByName("tail"), -1);
}

TEST(HumanoidTest, AModelWithoutAJointIsRefusedNamingIt) {
  MjModelPtr m = Load("football_pitch.xml");
  ASSERT_NE(m, nullptr);
  // Renaming in the compiled model: point the joint's name at another existing string.
  const int neck = mj_name2id(m.get(), mjOBJ_JOINT, "neck");
  m->name_jntadr[neck] = m->name_jntadr[mj_name2id(m.get(), mjOBJ_JOINT, "chest")];
  const absl::StatusOr<Joints> joints = ResolveJoints(m.get());
  ASSERT_FALSE(joints.ok());
  EXPECT_THAT(std::string(joints.status().message()), HasSubstr("'neck'"));
}

TEST(HumanoidTest, StablePdTorqueOfAKnownErrorIsTheHandWrittenOne) {
  MjModelPtr m = Load("football_pitch.xml");
  ASSERT_NE(m, nullptr);
  absl::StatusOr<Joints> joints = ResolveJoints(m.get());
  ASSERT_TRUE(joints.ok());
  MjDataPtr data(mj_makeData(m.get()));
  mjData* d = data.get();
  // The current pose: the model's rest pose; the right hip rotated by 0.3 rad about its z axis
  // and the right knee bent by −0.5 rad in the reference; some joint velocities.
  std::vector<double> reference(d->qpos, d->qpos + kCharacterNq);
  const ActuatedJoint& hip = (*joints)[kRightHip];
  const ActuatedJoint& knee = (*joints)[kRightKnee];
  const double angle = 0.3;
  // Reference = current ⊗ rotation about z: the error in the joint's frame is angle·ẑ.
  const double rotation[4] = {std::cos(angle / 2), 0, 0, std::sin(angle / 2)};
  mju_mulQuat(reference.data() + hip.qpos_adr, d->qpos + hip.qpos_adr, rotation);
  reference[knee.qpos_adr] = d->qpos[knee.qpos_adr] - 0.5;
  for (int i = 6; i < m->nv; ++i) d->qvel[i] = 0.01 * (i - 20);
  std::vector<double> feedforward(m->nv, 0.0), tau(m->nv, -7.0);
  feedforward[hip.dof_adr + 2] = 1.5;
  StablePdTorques(*joints, reference.data(), m.get(), d, feedforward.data(), tau.data());
  const double h = m->opt.timestep;
  // Hand-written: kp·(err − h·q̇) + feedforward.
  for (int k = 0; k < 3; ++k) {
    const double err = k == 2 ? angle : 0.0;
    const double ff = k == 2 ? 1.5 : 0.0;
    EXPECT_NEAR(tau[hip.dof_adr + k], hip.kp * (err - h * d->qvel[hip.dof_adr + k]) + ff, 1e-9);
  }
  EXPECT_NEAR(tau[knee.dof_adr], knee.kp * (-0.5 - h * d->qvel[knee.dof_adr]), 1e-12);
  // Joints at their reference: only the damping-free velocity term.
  const ActuatedJoint& neck = (*joints)[kNeck];
  EXPECT_NEAR(tau[neck.dof_adr], -neck.kp * h * d->qvel[neck.dof_adr], 1e-12);
  // The root's six entries are not the PD's.
  for (int i = 0; i < 6; ++i) EXPECT_EQ(tau[i], -7.0);
}

TEST(HumanoidTest, JointDampingIsTheGainsKd) {
  MjModelPtr m = Load("football_pitch.xml");
  ASSERT_NE(m, nullptr);
  absl::StatusOr<Joints> joints = ResolveJoints(m.get());
  ASSERT_TRUE(joints.ok());
  (*joints)[kLeftAnkle].kd = 42;
  WriteJointDamping(*joints, m.get());
  const ActuatedJoint& ankle = (*joints)[kLeftAnkle];
  for (int k = 0; k < 3; ++k) EXPECT_EQ(m->dof_damping[ankle.dof_adr + k], 42);
  EXPECT_EQ(m->dof_damping[(*joints)[kChest].dof_adr], DefaultGainsFor(kChest).kd);
  EXPECT_EQ(m->dof_damping[0], 0) << "the root is not a PD joint";
}

}  // namespace
}  // namespace juggle::humanoid
