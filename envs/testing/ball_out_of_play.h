// Test helper: the soccer ball held out of play — 40 m above the root plus the current node's
// ball target, at rest — so that a kick feedback sees no error and the character's stance is
// measured alone (envs/soccer_juggle/stance_test.cc, push_recovery_test.cc).
#ifndef JUGGLE_ENVS_TESTING_BALL_OUT_OF_PLAY_H_
#define JUGGLE_ENVS_TESTING_BALL_OUT_OF_PLAY_H_

#include <mujoco/mujoco.h>

#include "envs/soccer_juggle/env.h"

namespace juggle::testing {

// Call before every step of `env`.
inline void HoldBallOutOfPlay(const soccer_juggle::JuggleSpec& spec,
                              soccer_juggle::JuggleEnv* env) {
  mjData* d = env->data();
  const GraphNode& node = spec.graph().node(env->node());
  double* ball = d->qpos + spec.ball_qpos();
  ball[0] = d->qpos[0] + node.spec.ball_target().x();
  ball[1] = d->qpos[1] + node.spec.ball_target().y();
  ball[2] = 40.0;
  mju_zero(d->qvel + spec.ball_dof(), 6);
}

}  // namespace juggle::testing

#endif  // JUGGLE_ENVS_TESTING_BALL_OUT_OF_PLAY_H_
