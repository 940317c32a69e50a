#include "envs/humanoid/reference_dynamics.h"

namespace juggle::humanoid {

void ReferenceInverseDynamics(const Joints& joints, const mjModel* m, const mjData& data,
                              const CharacterPose& before, const CharacterPose& now,
                              const CharacterPose& after, double dt, mjData* d, double* tau) {
  constexpr double kLift = 100;  // m
  const int nq = m->nq, nv = m->nv;
  mjMARKSTACK;
  mjtNum* q_minus = mj_stackAlloc(d, nq);
  mjtNum* q_plus = mj_stackAlloc(d, nq);
  mjtNum* v_minus = mj_stackAlloc(d, nv);
  mjtNum* v_plus = mj_stackAlloc(d, nv);
  auto load = [&](const CharacterPose& p, mjtNum* qpos) {
    mju_copy(qpos, data.qpos, nq);  // the ball stays where it is, far below the character
    mju_copy(qpos, p.data(), kCharacterNq);
    qpos[2] += kLift;
  };
  load(now, d->qpos);
  load(before, q_minus);
  load(after, q_plus);
  mj_differentiatePos(m, v_minus, dt, q_minus, d->qpos);
  mj_differentiatePos(m, v_plus, dt, d->qpos, q_plus);
  for (int i = 0; i < nv; ++i) {
    d->qvel[i] = 0.5 * (v_minus[i] + v_plus[i]);
    d->qacc[i] = (v_plus[i] - v_minus[i]) / dt;
  }
  mju_zero(d->qvel, 6);
  mju_zero(d->qacc, 6);
  mju_zero(d->qvel + kCharacterNv, nv - kCharacterNv);
  mju_zero(d->qacc + kCharacterNv, nv - kCharacterNv);
  mj_inverse(m, d);
  const double h = m->opt.timestep;
  for (const ActuatedJoint& joint : joints) {
    for (int k = joint.dof_adr; k < joint.dof_adr + joint.dofs; ++k) {
      // qfrc_inverse includes the damping drag kd·q̇; kp·h·q̇ is the stable PD's own drag.
      tau[k] = d->qfrc_inverse[k] + joint.kp * h * d->qvel[k];
    }
  }
  mjFREESTACK;
}

}  // namespace juggle::humanoid
