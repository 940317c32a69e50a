// The ball's free path on the pitch for the football planning tasks' costs: flight above the
// turf, a slowing roll on it, nothing else in the way. Not the simulation: a cost's estimate of
// where a ball is going (trap_task.h, trap_kick_task.h).
#ifndef JUGGLE_PLANNER_FOOTBALL_FREE_BALL_H_
#define JUGGLE_PLANNER_FOOTBALL_FREE_BALL_H_

#include "envs/football/env.h"

namespace juggle::planner {

struct FreeBall {
  double p[3], v[3];
  double g, r, roll;

  // The ball's state in `e`.
  explicit FreeBall(const football::FootballEnv& e);
  // A step of `dt` seconds: of flight above the turf, or of roll (slowing) on it.
  void Step(double dt);
  bool on_turf() const { return p[2] <= r + 0.01 && v[2] <= 0; }
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_FOOTBALL_FREE_BALL_H_
