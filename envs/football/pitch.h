// The ball of a football pitch model (configs/models/football_pitch.xml): where it lives in the
// model and what the turf does to it, read from the model so that tests, passes and envs share
// one set of formulas (docs/football.md, "The pitch").
#ifndef JUGGLE_ENVS_FOOTBALL_PITCH_H_
#define JUGGLE_ENVS_FOOTBALL_PITCH_H_

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"

namespace juggle::football {

struct PitchBall {
  int body = -1, geom = -1;  // "ball"
  int qpos = 0, dof = 0;     // its free joint's addresses
  int turf_pair = -1;        // the contact pair "ball_on_turf"
  int pitch_geom = -1;       // "pitch"
  double radius = 0, mass = 0, inertia = 0;  // m, kg, kg·m² (about any axis)
};

// INVALID_ARGUMENT naming what the model lacks: a body "ball" with a free joint and a sphere
// geom "ball" with a direct (negative) solref and a positive priority (its contacts with the
// character use its parameters), a geom "pitch", a pair "ball_on_turf" with a direct solref.
absl::StatusOr<PitchBall> FindPitchBall(const mjModel* m);

// The rolling ball's deceleration on the turf (m/s²): a ball rolling without slipping under the
// rolling-resistance torque μ_r·N slows at μ_r·g / (r·(1 + I/(m·r²))).
double RollingDeceleration(const mjModel* m, const PitchBall& ball);

// The restitution of the turf pair's direct solref (−K, −D), a damped spring per unit mass:
// ζ = D / (2√K), e = exp(−πζ / √(1 − ζ²)).
double TurfRestitution(const mjModel* m, const PitchBall& ball);

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_PITCH_H_
