#include "envs/football/pitch.h"

#include <cmath>

namespace juggle::football {

absl::StatusOr<PitchBall> FindPitchBall(const mjModel* m) {
  PitchBall b;
  b.body = mj_name2id(m, mjOBJ_BODY, "ball");
  b.geom = mj_name2id(m, mjOBJ_GEOM, "ball");
  b.pitch_geom = mj_name2id(m, mjOBJ_GEOM, "pitch");
  b.turf_pair = mj_name2id(m, mjOBJ_PAIR, "ball_on_turf");
  if (b.body < 0 || b.geom < 0 || m->geom_type[b.geom] != mjGEOM_SPHERE) {
    return absl::InvalidArgumentError("the pitch model has no body \"ball\" with a sphere geom \"ball\"");
  }
  if (m->body_jntnum[b.body] != 1 || m->jnt_type[m->body_jntadr[b.body]] != mjJNT_FREE) {
    return absl::InvalidArgumentError("the pitch model's ball needs one free joint");
  }
  if (b.pitch_geom < 0) return absl::InvalidArgumentError("the pitch model has no geom \"pitch\"");
  if (b.turf_pair < 0 || m->pair_solref[mjNREF * b.turf_pair] >= 0 ||
      m->pair_solref[mjNREF * b.turf_pair + 1] >= 0) {
    return absl::InvalidArgumentError(
        "the pitch model needs a contact pair \"ball_on_turf\" with a direct solref (-K -D)");
  }
  if (m->geom_solref[mjNREF * b.geom] >= 0 || m->geom_solref[mjNREF * b.geom + 1] >= 0 ||
      m->geom_priority[b.geom] <= 0) {
    return absl::InvalidArgumentError(
        "the pitch model's ball geom needs a direct solref (-K -D) and a priority above the "
        "character's, so that its contacts with the body use it");
  }
  const int joint = m->body_jntadr[b.body];
  b.qpos = m->jnt_qposadr[joint];
  b.dof = m->jnt_dofadr[joint];
  b.radius = m->geom_size[3 * b.geom];
  b.mass = m->body_mass[b.body];
  b.inertia = m->body_inertia[3 * b.body];
  return b;
}

double RollingDeceleration(const mjModel* m, const PitchBall& b) {
  const double mu_roll = m->pair_friction[5 * b.turf_pair + 3];
  const double g = -m->opt.gravity[2];
  return mu_roll * g / (b.radius * (1 + b.inertia / (b.mass * b.radius * b.radius)));
}

double TurfRestitution(const mjModel* m, const PitchBall& b) {
  const double k = -m->pair_solref[mjNREF * b.turf_pair];
  const double damping = -m->pair_solref[mjNREF * b.turf_pair + 1];
  const double zeta = damping / (2 * std::sqrt(k));
  return std::exp(-M_PI * zeta / std::sqrt(1 - zeta * zeta));
}

}  // namespace juggle::football
