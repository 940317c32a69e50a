// Test helpers of the soccer planner's tests: a small, quick planner config and the kick the
// base controller makes with zero action.
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_TEST_KICKS_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_TEST_KICKS_H_

#include "common/adaptive_walk.h"
#include "common/config_loader.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "planner/soccer_juggle/cost.h"

namespace juggle::planner {

// A small, quick planner on `config`: kick variables only, 16 samples × 4 iterations, a
// 32-step horizon re-planned every 4 steps.
inline void UseSmallPlanner(LoadedConfig* config) {
  config::PlannerConfig& p = *config->run.mutable_planner();
  p.set_samples(16);
  p.set_iterations(4);
  p.set_horizon_steps(32);
  p.set_replan_every(4);
  p.set_body_knot_steps(0);
}

// configs/right_foot_planner.textproto with UseSmallPlanner's settings.
inline absl::StatusOr<LoadedConfig> SmallRightFootPlanner() {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(::juggle::testing::RepoPath("configs/right_foot_planner.textproto"));
  if (config.ok()) UseSmallPlanner(&*config);
  return config;
}

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
