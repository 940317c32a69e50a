#include "envs/soccer_juggle/base_controller.h"

#include <algorithm>

#include "envs/ballistic.h"

namespace juggle::soccer_juggle {

BaseController::BaseController(const JuggleSpec& spec)
    : spec_(spec), model_(spec.model()) {
  if (spec_.env().reference_feedforward() != 0) id_data_.reset(mj_makeData(model_));
}

void BaseController::UpdateSwingAdjust(const mjData& data, const CursorState& cursor,
                                       bool kick_touched, SwingAdjust* adjust) const {
  if (!spec_.env().has_kick_feedback()) return;
  const GraphNode& node = spec_.graph().node(cursor.current);
  if (node.stage != config::DOWN || kick_touched || !node.spec.pose().has_leg_swing()) return;
  const double* qpos = data.qpos;
  const double* ball = qpos + spec_.ball_qpos();
  const double* ball_vel = data.qvel + spec_.ball_dof();
  if (ball[2] - node.spec.contact_height() <= 0) return;  // at the contact height already: hold
  const BallisticCrossing c =
      DescendingCrossing(ball, ball_vel, spec_.env().gravity(), node.spec.contact_height());
  const double ex = c.x - qpos[0] - node.spec.ball_target().x();
  const double ey = c.y - qpos[1] - node.spec.ball_target().y();
  const double late = c.t + spec_.cursor().SecondsFromContact(cursor, cursor.phase);
  const config::KickFeedback& f = spec_.env().kick_feedback();
  const bool left = node.spec.pose().leg_swing().side() == config::LEFT;
  adjust->hip = f.hip_per_m() * ex;
  adjust->knee = f.knee_per_m() * ex;
  adjust->abduction = f.abduction_per_m() * ey * (left ? 1 : -1);
  const double cycle_s = spec_.control_dt() / cursor.phase_speed;
  adjust->phase = -f.timing() * late / cycle_s;
}

void BaseController::AddFeedforward(const CursorState& cursor, const CharacterPose& reference,
                                    const SwingAdjust& adjust, mjData* data,
                                    double* feedforward) {
  if (id_data_ != nullptr) AddReferenceFeedforward(cursor, reference, adjust, *data, feedforward);
  if (spec_.env().has_stance_balance()) AddStanceBalance(cursor, data, feedforward);
}

void BaseController::AddReferenceFeedforward(const CursorState& cursor,
                                             const CharacterPose& reference,
                                             const SwingAdjust& adjust, const mjData& data,
                                             double* feedforward) {
  // Reference pose, velocity and acceleration by central differences over ± half a control
  // step; the character is lifted out of contact and its root held still (qacc 0).
  constexpr double kLift = 100;  // m
  const int nq = model_->nq, nv = model_->nv;
  const double dt = 0.5 * spec_.control_dt();
  const double dphase = 0.5 * cursor.phase_speed;
  mjData* d = id_data_.get();
  mjMARKSTACK;
  mjtNum* q_minus = mj_stackAlloc(d, nq);
  mjtNum* q_plus = mj_stackAlloc(d, nq);
  mjtNum* v_minus = mj_stackAlloc(d, nv);
  mjtNum* v_plus = mj_stackAlloc(d, nv);
  CharacterPose pose;
  auto load = [&](const CharacterPose& p, mjtNum* qpos) {
    mju_copy(qpos, data.qpos, nq);  // the ball stays where it is, far below the character
    mju_copy(qpos, p.data(), kCharacterNq);
    qpos[2] += kLift;
  };
  load(reference, d->qpos);
  ComputeReferencePose(spec_, cursor.current, cursor.phase - dphase, &pose, adjust);
  load(pose, q_minus);
  ComputeReferencePose(spec_, cursor.current, cursor.phase + dphase, &pose, adjust);
  load(pose, q_plus);
  mj_differentiatePos(model_, v_minus, dt, q_minus, d->qpos);
  mj_differentiatePos(model_, v_plus, dt, d->qpos, q_plus);
  for (int i = 0; i < nv; ++i) {
    d->qvel[i] = 0.5 * (v_minus[i] + v_plus[i]);
    d->qacc[i] = (v_plus[i] - v_minus[i]) / dt;
  }
  mju_zero(d->qvel, 6);
  mju_zero(d->qacc, 6);
  mju_zero(d->qvel + spec_.ball_dof(), 6);
  mju_zero(d->qacc + spec_.ball_dof(), 6);
  mj_inverse(model_, d);
  const double gain = spec_.env().reference_feedforward();
  const double h = model_->opt.timestep;
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_.joint(j);
    for (int k = joint.dof_adr; k < joint.dof_adr + joint.dofs; ++k) {
      // qfrc_inverse includes the damping drag kd·q̇; kp·h·q̇ is the stable PD's own drag.
      feedforward[k] += gain * (d->qfrc_inverse[k] + joint.kp * h * d->qvel[k]);
    }
  }
  mjFREESTACK;
}

void BaseController::AddStanceBalance(const CursorState& cursor, mjData* data,
                                      double* feedforward) const {
  const config::StanceBalance& b = spec_.env().stance_balance();
  const config::ReferencePose& ref = spec_.graph().node(cursor.current).spec.pose();
  if (!ref.has_leg_swing()) return;
  const bool kick_left = ref.leg_swing().side() == config::LEFT;
  const ActuatedJoint& hip = spec_.joint(kick_left ? kRightHip : kLeftHip);
  const ActuatedJoint& ankle = spec_.joint(kick_left ? kRightAnkle : kLeftAnkle);
  const int foot = model_->dof_bodyid[ankle.dof_adr];
  // Each term is clamped to the joint's feed-forward range, as a policy action would be.
  auto add = [&](const ActuatedJoint& joint, const double tau[3]) {
    const double limit = spec_.env().action_torque() * joint.torque_scale;
    for (int i = 0; i < 3; ++i) {
      feedforward[joint.dof_adr + i] += std::clamp(tau[i], -limit, limit);
    }
  };
  double tau_ankle[3] = {0, 0, 0}, tau_hip[3] = {0, 0, 0};
  if (b.com_kp() != 0 || b.com_kd() != 0) {
    mj_subtreeVel(model_, data);  // COM velocity of the character (the root's subtree)
    const int root = spec_.root_body();
    const double* com = data->subtree_com + 3 * root;
    const double* vel = data->subtree_linvel + 3 * root;
    const double* pos = data->xpos + 3 * foot;
    const double ex = com[0] - pos[0] - b.com_x(), ey = com[1] - pos[1] - b.com_y();
    const double world[3] = {-(b.com_kp() * ey + b.com_kd() * vel[1]),
                             b.com_kp() * ex + b.com_kd() * vel[0], 0};
    mju_mulMatTVec(tau_ankle, data->xmat + 9 * foot, world, 3, 3);  // into the foot frame
  }
  if (b.pelvis_kp() != 0 || b.pelvis_kd() != 0 || b.yaw_kp() != 0 || b.yaw_kd() != 0) {
    double tilt[3];
    mju_subQuat(tilt, data->qpos + 3, kUprightQuat);
    const double* w = data->qvel + 3;
    for (int i : {0, 2}) tau_hip[i] = b.pelvis_kp() * tilt[i] + b.pelvis_kd() * w[i];
    tau_hip[1] = b.yaw_kp() * tilt[1] + b.yaw_kd() * w[1];  // about the root's vertical (y)
  }
  add(ankle, tau_ankle);
  add(hip, tau_hip);
}

}  // namespace juggle::soccer_juggle
