// The ball's free path on the pitch for the football planning tasks' costs: flight above the
// turf, a slowing roll on it, nothing else in the way; with `bounces`, a landing ball rebounds
// at the turf pair's restitution (envs/football/pitch.h, TurfRestitution) until its rebound
// would rise less than 1 cm, and only then rolls. Not the simulation: a cost's estimate of where
// a ball is going (trap_task.h, trap_kick_task.h).
#ifndef JUGGLE_PLANNER_FOOTBALL_FREE_BALL_H_
#define JUGGLE_PLANNER_FOOTBALL_FREE_BALL_H_

#include <mujoco/mujoco.h>

#include "envs/football/env.h"
#include "envs/football/spec.h"

namespace juggle::planner {

struct FreeBall {
  double p[3], v[3];
  double g, r, roll;
  double bounce = 0;  // the turf's restitution with `bounces`; 0: a landing ball rolls at once

  // The ball's state in `d` (a data of `spec`'s model), or in `e`.
  FreeBall(const football::FootballSpec& spec, const mjData* d, bool bounces = false);
  explicit FreeBall(const football::FootballEnv& e, bool bounces = false)
      : FreeBall(e.spec(), e.data(), bounces) {}
  // A step of `dt` seconds: of flight above the turf (a landing within it rebounds, with
  // bounces), or of roll (slowing) on it.
  void Step(double dt);
  bool on_turf() const { return p[2] <= r + 0.01 && v[2] <= 0; }
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_FOOTBALL_FREE_BALL_H_
