// The reward terms of Chemin & Lee (MIG 2018) §4, Eq. 5 and 8 (docs/toss.md), shared by the single-arm tasks
// (TossTaskEnv) and in-loop training (TossLoopEnv). Units: m, m/s. Pure functions.
#ifndef JUGGLE_ENVS_TOSS_REWARD_H_
#define JUGGLE_ENVS_TOSS_REWARD_H_

#include <algorithm>

#include "envs/toss/world.h"
#include "proto/envs/toss.pb.h"

namespace juggle::toss {

// −w·effort every step: w1 for the catch task, w3 for the throw task.
inline double EffortReward(const config::TossConfig& t, double effort) {
  return -(t.task() == config::THROW ? t.w_throw_effort() : t.w_catch_effort()) * effort;
}

// At a catch: −w2·min(|z̄ − z|, 1) with the height error |z̄ − z| of the ball, and
// −w_catch_speed·|ṗ_hand| (0 in the paper): a hand that arrives moving leaves the throw that
// follows less time to reach its release state.
inline double CatchReward(const config::TossConfig& t, double height_error_m,
                          double palm_speed_m_s) {
  return -t.w_catch_height() * std::min(height_error_m, 1.0) - t.w_catch_speed() * palm_speed_m_s;
}

// A drop (or a ball that misses its beat): −w2.
inline double DropReward(const config::TossConfig& t) { return -t.w_catch_height(); }

// At the release: −w4·|p̄ − p|² − w5·|v̄ − v|² for position and velocity errors (p − p̄, v − v̄).
inline double ReleaseReward(const config::TossConfig& t, Vec2 position_error,
                            Vec2 velocity_error) {
  const Vec2& dp = position_error;
  const Vec2& dv = velocity_error;
  return -t.w_release_position() * (dp.x * dp.x + dp.z * dp.z) -
         t.w_release_velocity() * (dv.x * dv.x + dv.z * dv.z);
}

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_REWARD_H_
