#include "planner/football/free_ball.h"

#include <algorithm>
#include <cmath>

#include "envs/football/pitch.h"

namespace juggle::planner {

FreeBall::FreeBall(const football::FootballEnv& e) {
  const football::FootballSpec& spec = e.spec();
  mju_copy3(p, e.data()->qpos + spec.ball().qpos);
  mju_copy3(v, e.data()->qvel + spec.ball().dof);
  g = -spec.model()->opt.gravity[2];
  r = spec.ball().radius;
  roll = football::RollingDeceleration(spec.model(), spec.ball());
}

void FreeBall::Step(double dt) {
  if (p[2] > r + 0.01 || v[2] > 0) {
    for (int c = 0; c < 3; ++c) p[c] += v[c] * dt;
    p[2] -= 0.5 * g * dt * dt;
    v[2] -= g * dt;
    if (p[2] < r) p[2] = r;
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
