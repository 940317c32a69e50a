#include "envs/football/trap_kick.h"

#include <algorithm>
#include <cmath>

#include "envs/football/spec.h"

namespace juggle::football {
namespace {

// A ball rolling back toward the foot faster than this (m/s) is not kickable: it would meet
// the standing foot before the swing, and that touch would count as the kick's.
constexpr double kMaxBackRollMps = 0.05;

}  // namespace

double KickZoneDistance(const FootballSpec& spec, double x, double y) {
  const config::TrapThenKick& z = spec.football().trap_kick();
  const double* foot = spec.kick_foot_standing();
  const double ahead = x - foot[0];
  const double out_x = std::max({0.0, z.zone_ahead_min_m() - ahead, ahead - z.zone_ahead_max_m()});
  const double out_y = std::max(0.0, std::abs(y - foot[1]) - z.zone_side_m());
  return std::hypot(out_x, out_y);
}

bool BallKickable(const FootballSpec& spec, const mjData* d) {
  const config::TrapThenKick& z = spec.football().trap_kick();
  const PitchBall& b = spec.ball();
  const double* p = d->qpos + b.qpos;
  const double* v = d->qvel + b.dof;
  if (p[2] > b.radius + z.zone_height_m()) return false;
  // Rolling slowly; a small hop (its height bounded above) may go on.
  if (std::hypot(v[0], v[1]) > z.max_speed_mps()) return false;
  if (v[0] < -kMaxBackRollMps) return false;
  if (KickZoneDistance(spec, p[0], p[1]) > 0) return false;
  const mjModel* m = spec.model();
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.geom1 != b.geom && c.geom2 != b.geom) continue;
    const int body = m->geom_bodyid[c.geom1 == b.geom ? c.geom2 : c.geom1];
    if (body != 0 && body != spec.kick_foot_body()) return false;  // 0: the turf
  }
  return true;
}

bool BallTouchesCharacter(const FootballSpec& spec, const mjData* d) {
  const int ball = spec.ball().geom;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.geom1 != ball && c.geom2 != ball) continue;
    if (spec.model()->geom_bodyid[c.geom1 == ball ? c.geom2 : c.geom1] != 0) return true;
  }
  return false;
}

}  // namespace juggle::football
