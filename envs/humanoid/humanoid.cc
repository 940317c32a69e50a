#include "envs/humanoid/humanoid.h"

#include "absl/strings/str_cat.h"

namespace juggle::humanoid {

const char* const kJointNames[kNumJoints] = {
    "chest", "neck", "right_shoulder", "right_elbow", "left_shoulder", "left_elbow",
    "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee", "left_ankle"};

DefaultGains DefaultGainsFor(JointId j) {
  switch (j) {
    case kChest: return {250, 25, 1.0};
    case kNeck: return {50, 5, 0.5};
    case kRightShoulder: case kRightElbow: case kLeftShoulder: case kLeftElbow:
      return {50, 5, 0.5};
    case kRightHip: case kRightKnee: case kLeftHip: case kLeftKnee: return {250, 25, 2.5};
    case kRightAnkle: case kLeftAnkle: return {150, 15, 1.5};
    default: return {0, 0, 0};
  }
}

int JointIdByName(const std::string& name) {
  for (int j = 0; j < kNumJoints; ++j) {
    if (name == kJointNames[j]) return j;
  }
  return -1;
}

absl::StatusOr<Joints> ResolveJoints(const mjModel* m) {
  Joints joints;
  int expected_qpos = 7, expected_dof = 6;  // after the root free joint
  for (int j = 0; j < kNumJoints; ++j) {
    const int id = mj_name2id(m, mjOBJ_JOINT, kJointNames[j]);
    if (id < 0) {
      return absl::InvalidArgumentError(
          absl::StrCat("the model has no joint '", kJointNames[j], "'"));
    }
    ActuatedJoint& joint = joints[j];
    joint.qpos_adr = m->jnt_qposadr[id];
    joint.dof_adr = m->jnt_dofadr[id];
    joint.dofs = m->jnt_type[id] == mjJNT_BALL ? 3 : 1;
    if (joint.qpos_adr != expected_qpos || joint.dof_adr != expected_dof) {
      return absl::InvalidArgumentError(
          absl::StrCat("joint '", kJointNames[j], "' is out of the expected order"));
    }
    expected_qpos += joint.dofs == 3 ? 4 : 1;
    expected_dof += joint.dofs;
    const DefaultGains g = DefaultGainsFor(static_cast<JointId>(j));
    joint.kp = g.kp;
    joint.kd = g.kd;
    joint.torque_scale = g.scale;
  }
  return joints;
}

void WriteJointDamping(const Joints& joints, mjModel* m) {
  for (const ActuatedJoint& joint : joints) {
    for (int d = 0; d < joint.dofs; ++d) m->dof_damping[joint.dof_adr + d] = joint.kd;
  }
}

void StablePdTorques(const Joints& joints, const double* reference, const mjModel* m,
                     const mjData* d, const double* feedforward, double* tau) {
  const double h = m->opt.timestep;
  const double* qpos = d->qpos;
  const double* qvel = d->qvel;
  for (const ActuatedJoint& joint : joints) {
    const int dof = joint.dof_adr;
    if (joint.dofs == 3) {
      double err[3];
      mju_subQuat(err, reference + joint.qpos_adr, qpos + joint.qpos_adr);
      for (int k = 0; k < 3; ++k) {
        tau[dof + k] = joint.kp * (err[k] - h * qvel[dof + k]) + feedforward[dof + k];
      }
    } else {
      const double err = reference[joint.qpos_adr] - qpos[joint.qpos_adr];
      tau[dof] = joint.kp * (err - h * qvel[dof]) + feedforward[dof];
    }
  }
}

}  // namespace juggle::humanoid
