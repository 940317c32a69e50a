#include "planner/football/free_ball.h"

#include <algorithm>
#include <cmath>

#include "envs/football/pitch.h"

namespace juggle::planner {
namespace {

// A rebound slower than this (m/s) rises less than 1 cm (v² / 2g): the ball rolls from there.
constexpr double kSettleSpeed = 0.44;

}  // namespace

FreeBall::FreeBall(const football::FootballSpec& spec, const mjData* d, bool bounces) {
  mju_copy3(p, d->qpos + spec.ball().qpos);
  mju_copy3(v, d->qvel + spec.ball().dof);
  g = -spec.model()->opt.gravity[2];
  r = spec.ball().radius;
  roll = football::RollingDeceleration(spec.model(), spec.ball());
  if (bounces) bounce = football::TurfRestitution(spec.model(), spec.ball());
}

void FreeBall::Step(double dt) {
  // Without bounces a ball within 1 cm of the turf rolls; with them it flies until it lands.
  if (p[2] > r + (bounce > 0 ? 1e-9 : 0.01) || v[2] > 0) {
    for (int c = 0; c < 3; ++c) p[c] += v[c] * dt;
    p[2] -= 0.5 * g * dt * dt;
    v[2] -= g * dt;
    if (p[2] < r) {
      p[2] = r;
      // Landed within the step: a rebound, or the end of the flight.
      v[2] = bounce * -v[2] > kSettleSpeed ? bounce * -v[2] : 0;
    }
    return;
  }
  const double speed = std::hypot(v[0], v[1]);
  if (speed < 1e-3) return;
  const double slower = std::max(0.0, speed - roll * dt) / speed;
  for (int c = 0; c < 2; ++c) {
    p[c] += v[c] * dt;
    v[c] *= slower;
  }
  v[2] = 0;
}

}  // namespace juggle::planner
