#include "envs/humanoid/pose.h"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace juggle::humanoid {

void SetBallJointRotation(const Joints& joints, JointId j, const double rotvec[3],
                          CharacterPose* pose) {
  double* q = pose->data() + joints[j].qpos_adr;
  double v[3] = {rotvec[0], rotvec[1], rotvec[2]};
  const double angle = mju_normalize3(v);
  if (angle < 1e-12) {
    q[0] = 1;
    q[1] = q[2] = q[3] = 0;
    return;
  }
  mju_axisAngle2Quat(q, v, angle);
}

void SetHinge(const Joints& joints, JointId j, double angle, CharacterPose* pose) {
  (*pose)[joints[j].qpos_adr] = angle;
}

CharacterPose ReleaseRestPose(const Joints& joints) {
  CharacterPose pose;
  std::fill(pose.begin(), pose.end(), 0.0);
  for (const ActuatedJoint& joint : joints) {
    if (joint.dofs == 3) pose[joint.qpos_adr] = 1.0;  // identity quaternion
  }
  SetHinge(joints, kRightElbow, 1.57, &pose);
  SetHinge(joints, kLeftElbow, 1.57, &pose);
  const double right[3] = {-0.7, 0, 0}, left[3] = {0.7, 0, 0};
  SetBallJointRotation(joints, kRightShoulder, right, &pose);
  SetBallJointRotation(joints, kLeftShoulder, left, &pose);
  return pose;
}

absl::Status ApplyJointRotation(const Joints& joints, const config::JointRotation& r,
                                CharacterPose* pose, std::string* field) {
  const int j = JointIdByName(r.joint());
  if (j < 0) {
    *field = "joint";
    return absl::InvalidArgumentError(absl::StrCat("unknown joint '", r.joint(), "'"));
  }
  const int want = joints[j].dofs;
  if (r.value_size() != want) {
    *field = "value";
    return absl::InvalidArgumentError(absl::StrCat("joint '", r.joint(), "' takes ", want,
                                                   " value(s), got ", r.value_size()));
  }
  if (want == 3) {
    const double v[3] = {r.value(0), r.value(1), r.value(2)};
    SetBallJointRotation(joints, static_cast<JointId>(j), v, pose);
  } else {
    SetHinge(joints, static_cast<JointId>(j), r.value(0), pose);
  }
  return absl::OkStatus();
}

}  // namespace juggle::humanoid
