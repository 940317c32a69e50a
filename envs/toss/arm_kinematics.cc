#include "envs/toss/arm_kinematics.h"

#include <cmath>

#include <mujoco/mujoco.h>

namespace juggle::toss {
namespace {

// A link of length L at absolute angle φ (hinge about +y) points along (−sin φ, −cos φ).
Vec2 Link(double length, double phi) { return {-length * std::sin(phi), -length * std::cos(phi)}; }

}  // namespace

ArmGeometry ReadArmGeometry(const TossSpec& spec) {
  const mjModel* m = spec.model();
  MjDataPtr data(mj_makeData(m));
  mjData* d = data.get();
  mj_kinematics(m, d);  // qpos 0: every link hangs straight down
  const TossArmJoints& arm = spec.arm(Hand::kRight);
  auto anchor = [&](int j) {
    const int joint = m->dof_jntid[arm.dof[j]];
    return Vec2{d->xanchor[3 * joint], d->xanchor[3 * joint + 2]};
  };
  const Vec2 s = anchor(1), e = anchor(2), w = anchor(3);
  const Vec2 p{d->site_xpos[3 * arm.palm_site], d->site_xpos[3 * arm.palm_site + 2]};
  ArmGeometry g;
  g.shoulder = s;
  g.length = {std::hypot(e.x - s.x, e.z - s.z), std::hypot(w.x - e.x, w.z - e.z),
              std::hypot(p.x - w.x, p.z - w.z)};
  g.elbow_sign = spec.home()[2] >= 0 ? 1.0 : -1.0;
  return g;
}

Vec2 PalmPosition(const ArmGeometry& g, const ArmAngles& q) {
  Vec2 p = g.shoulder;
  double phi = 0;
  for (int i = 0; i < 3; ++i) {
    phi += q[i];
    const Vec2 l = Link(g.length[i], phi);
    p.x += l.x;
    p.z += l.z;
  }
  return p;
}

std::array<ArmAngles, 2> PalmJacobian(const ArmGeometry& g, const ArmAngles& q) {
  // ∂/∂q_i of Σ_{k≥i} Link(L_k, φ_k) = Σ_{k≥i} L_k·(−cos φ_k, sin φ_k).
  std::array<ArmAngles, 2> jac{};
  double phi[3];
  phi[0] = q[0];
  phi[1] = phi[0] + q[1];
  phi[2] = phi[1] + q[2];
  for (int i = 0; i < 3; ++i) {
    for (int k = i; k < 3; ++k) {
      jac[0][i] += -g.length[k] * std::cos(phi[k]);
      jac[1][i] += g.length[k] * std::sin(phi[k]);
    }
  }
  return jac;
}

std::optional<ArmAngles> SolveArmIk(const ArmGeometry& g, Vec2 palm, double hand_angle) {
  const Vec2 hand = Link(g.length[2], hand_angle);
  const double dx = palm.x - hand.x - g.shoulder.x, dz = palm.z - hand.z - g.shoulder.z;
  const double l1 = g.length[0], l2 = g.length[1];
  const double cos_elbow = (dx * dx + dz * dz - l1 * l1 - l2 * l2) / (2 * l1 * l2);
  if (!(std::abs(cos_elbow) <= 1)) return std::nullopt;
  const double qe = g.elbow_sign * std::acos(cos_elbow);
  const double qs = std::atan2(-dx, -dz) - std::atan2(l2 * std::sin(qe), l1 + l2 * std::cos(qe));
  return ArmAngles{qs, qe, hand_angle - qs - qe};
}

ArmAngles JointSpeedsFor(const ArmGeometry& g, const ArmAngles& q, Vec2 palm_velocity,
                         double wrist_weight) {
  // q̇ = W⁻¹Jᵀ(J W⁻¹ Jᵀ)⁻¹ v.
  const std::array<ArmAngles, 2> jac = PalmJacobian(g, q);
  const ArmAngles w_inv = {1.0, 1.0, 1.0 / wrist_weight};
  double a[2][2] = {};
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      for (int j = 0; j < 3; ++j) a[r][c] += jac[r][j] * w_inv[j] * jac[c][j];
    }
  }
  const double det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  const double y0 = (a[1][1] * palm_velocity.x - a[0][1] * palm_velocity.z) / det;
  const double y1 = (a[0][0] * palm_velocity.z - a[1][0] * palm_velocity.x) / det;
  ArmAngles speeds{};
  for (int j = 0; j < 3; ++j) speeds[j] = w_inv[j] * (jac[0][j] * y0 + jac[1][j] * y1);
  return speeds;
}

}  // namespace juggle::toss
