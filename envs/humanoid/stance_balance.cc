#include "envs/humanoid/stance_balance.h"

#include <algorithm>
#include <cmath>

namespace juggle::humanoid {

double Heading(const double* xmat) { return std::atan2(xmat[3], xmat[0]); }

void AddStanceBalance(const Joints& joints, const config::StanceBalance& b, Foot stance,
                      int root_body, double action_torque, const mjModel* m, mjData* data,
                      double* feedforward) {
  const bool left = stance == Foot::kLeft;
  const ActuatedJoint& hip = joints[left ? kLeftHip : kRightHip];
  const ActuatedJoint& ankle = joints[left ? kLeftAnkle : kRightAnkle];
  const int foot = m->dof_bodyid[ankle.dof_adr];
  auto add = [&](const ActuatedJoint& joint, const double tau[3]) {
    const double limit = action_torque * joint.torque_scale;
    for (int i = 0; i < 3; ++i) {
      feedforward[joint.dof_adr + i] += std::clamp(tau[i], -limit, limit);
    }
  };
  double tau_ankle[3] = {0, 0, 0}, tau_hip[3] = {0, 0, 0};
  if (b.com_kp() != 0 || b.com_kd() != 0) {
    mj_subtreeVel(m, data);  // COM velocity of the character (the root's subtree)
    const double* com = data->subtree_com + 3 * root_body;
    const double* vel = data->subtree_linvel + 3 * root_body;
    const double* pos = data->xpos + 3 * foot;
    const double ex = com[0] - pos[0] - b.com_x(), ey = com[1] - pos[1] - b.com_y();
    const double world[3] = {-(b.com_kp() * ey + b.com_kd() * vel[1]),
                             b.com_kp() * ex + b.com_kd() * vel[0], 0};
    mju_mulMatTVec(tau_ankle, data->xmat + 9 * foot, world, 3, 3);  // into the foot frame
    if (b.hip_roll() != 0 || b.hip_pitch() != 0) {  // the same on the pelvis, through the hip
      const double on_thigh[3] = {-b.hip_roll() * world[0], -b.hip_pitch() * world[1], 0};
      mju_mulMatTVec(tau_hip, data->xmat + 9 * m->dof_bodyid[hip.dof_adr], on_thigh, 3, 3);
    }
  }
  if (b.pelvis_kp() != 0 || b.pelvis_kd() != 0 || b.yaw_kp() != 0 || b.yaw_kd() != 0) {
    double tilt[3];
    mju_subQuat(tilt, data->qpos + 3, kUprightRoot);
    const double* w = data->qvel + 3;
    for (int i : {0, 2}) tau_hip[i] += b.pelvis_kp() * tilt[i] + b.pelvis_kd() * w[i];
    double yaw = tilt[1];  // about the root's vertical (y), from the world's forward
    if (b.yaw_from_stance_foot()) {
      const double off = Heading(data->xmat + 9 * root_body) - Heading(data->xmat + 9 * foot);
      yaw = std::remainder(off, 2 * M_PI);
    }
    tau_hip[1] += b.yaw_kp() * yaw + b.yaw_kd() * w[1];
  }
  add(ankle, tau_ankle);
  add(hip, tau_hip);
}

void AddDoubleStanceBalance(const Joints& joints, const config::StanceBalance& gains, int root_body,
                            double action_torque, const mjModel* m, mjData* data,
                            double* feedforward) {
  const double* left = data->xpos + 3 * m->dof_bodyid[joints[kLeftAnkle].dof_adr];
  const double* right = data->xpos + 3 * m->dof_bodyid[joints[kRightAnkle].dof_adr];
  for (Foot stance : {Foot::kLeft, Foot::kRight}) {
    const double* own = stance == Foot::kLeft ? left : right;
    const double* other = stance == Foot::kLeft ? right : left;
    config::StanceBalance half = gains;
    half.set_com_kp(gains.com_kp() / 2);
    half.set_com_kd(gains.com_kd() / 2);
    half.set_pelvis_kp(gains.pelvis_kp() / 2);
    half.set_pelvis_kd(gains.pelvis_kd() / 2);
    half.set_yaw_kp(gains.yaw_kp() / 2);
    half.set_yaw_kd(gains.yaw_kd() / 2);
    // The target from this ankle: to the midpoint, then the configured offset.
    half.set_com_x(gains.com_x() + (other[0] - own[0]) / 2);
    half.set_com_y(gains.com_y() + (other[1] - own[1]) / 2);
    AddStanceBalance(joints, half, stance, root_body, action_torque, m, data, feedforward);
  }
}

}  // namespace juggle::humanoid
