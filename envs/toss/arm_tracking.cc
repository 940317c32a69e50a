#include "envs/toss/arm_tracking.h"

#include <vector>

#include <mujoco/mujoco.h>

namespace juggle::toss {

ArmAngles FirstPlannedAcceleration(const ArmAngles& q, const ArmAngles& v, const ArmAngles& q_goal,
                                   const ArmAngles& v_goal, int steps, double h) {
  ArmAngles a0{};
  const double n = steps;
  for (int j = 0; j < 3; ++j) {
    // Σ_k a_k = A and Σ_k (n − k)·a_k = B, with a_k = λ1 + λ2·(n − k) (Lagrange).
    const double big_a = (v_goal[j] - v[j]) / h;
    if (steps <= 1) {
      a0[j] = big_a;
      continue;
    }
    const double big_b = (q_goal[j] - q[j] - h * n * v[j]) / (h * h);
    const double s0 = n, s1 = n * (n + 1) / 2, s2 = n * (n + 1) * (2 * n + 1) / 6;
    const double det = s0 * s2 - s1 * s1;
    const double l1 = (big_a * s2 - big_b * s1) / det;
    const double l2 = (big_b * s0 - big_a * s1) / det;
    a0[j] = l1 + l2 * n;
  }
  return a0;
}

ArmAngles TargetsForAcceleration(const TossWorld& world, Hand hand, const ArmAngles& qacc) {
  const TossSpec& spec = world.spec();
  const mjModel* m = spec.model();
  const mjData* d = world.data();
  const TossArmJoints& arm = spec.arm(hand);
  const double mirror = TossSpec::MirrorSign(hand), h = spec.dt(), kp = spec.toss().kp();
  std::vector<mjtNum> full(m->nv * m->nv);
  mj_fullM(m, full.data(), d->qM);
  ArmAngles tau{};
  for (int r = 0; r < 3; ++r) {
    const int dr = arm.dof[r + 1];
    for (int c = 0; c < 3; ++c) {
      const int dc = arm.dof[c + 1];
      const double mass = full[dr * m->nv + dc] + (r == c ? h * m->dof_damping[dr] : 0.0);
      tau[r] += mass * mirror * qacc[c];
    }
    tau[r] += m->dof_damping[dr] * d->qvel[dr] + d->qfrc_bias[dr];
  }
  if (const int ball = world.held_by(hand); ball >= 0) {
    // The world pulls the palm down by the ball's weight (TossWorld::Step); hold it up.
    std::vector<mjtNum> jacp(3 * m->nv);
    mj_jacSite(m, d, jacp.data(), nullptr, arm.palm_site);
    const double weight =
        m->body_mass[m->dof_bodyid[spec.ball(ball).dof_x]] * spec.timing().gravity;
    for (int r = 0; r < 3; ++r) tau[r] += jacp[2 * m->nv + arm.dof[r + 1]] * weight;
  }
  ArmAngles targets{};
  for (int r = 0; r < 3; ++r) {
    const int dof = arm.dof[r + 1];
    targets[r] = d->qpos[arm.qpos[r + 1]] + h * d->qvel[dof] + tau[r] / kp;
  }
  return targets;
}

}  // namespace juggle::toss
