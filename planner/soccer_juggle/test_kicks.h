// Test helper: the kick the base controller makes with zero action (planner tests).
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_TEST_KICKS_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_TEST_KICKS_H_

#include "common/adaptive_walk.h"
#include "envs/soccer_juggle/env.h"
#include "planner/soccer_juggle/cost.h"

namespace juggle::planner {

// Steps `env` with zero action until its kick leaves the contact body (or the episode ends, or
// 60 steps pass); returns the kick's outcome (invalid if there was none).
inline KickOutcome ZeroActionKick(soccer_juggle::JuggleEnv* env, const AdaptiveWalk& walk) {
  const float zero[soccer_juggle::kNumActions] = {0};
  for (int t = 0; t < 60; ++t) {
    if (env->Step(zero, walk).outcome != Outcome::kRunning) return {};
    if (env->state().kick_touched && !env->state().touched_this_step) {
      return PredictKickOutcome(*env);
    }
  }
  return {};
}

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_JUGGLE_TEST_KICKS_H_
