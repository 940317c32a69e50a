// The soccer-juggling reward of one control step, term by term (docs/environment.md, "Reward";
// weights in RewardConfig, proto/envs/soccer_juggle.proto):
//
//   reward = float(scale·(1 + 2 + 3 + 4)) + 5          (RewardTerms::Total, in this order)
//
//   1. position     w_position·exp(−(v_x² + v_y² + (z − z_ref)²))      root speed and height
//   2. orientation  w_orientation·exp(−orientation_k·sin²(θ/2))        root vs reference rotation
//   3. joint        w_joint·exp(−joint_k·Σ e_j)   e_j: sin²(θ/2) per ball joint, Δq² per hinge
//   4. ball         w_ball·exp(−(dx² + dy² + ball_z_weight·dz²))        ball vs its reference
//   5. kick         w_kick·exp(−kick_apex_k·(apex − H)² − kick_landing_k·|landing − target|²)
//
// Terms 1–4 are the release's (max 0.1 per step at its weights): the state after the step
// against the reference pose and ball reference of the step's start. Term 5 (not in the
// release; off at w_kick 0) is paid once per kick, at the first step after the ball leaves an
// allowed body going up: the ball's ballistic apex against the next DOWN node's apex H, and
// where it comes down through that node's contact height against its ball target (relative to
// the root). A diverged step earns 0 (every term 0); a step that ends the episode earns no
// term 5. Pure functions of the state.
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_REWARD_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_REWARD_H_

#include <mujoco/mujoco.h>

#include "envs/soccer_juggle/graph_cursor.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {

struct RewardTerms {
  double position = 0, orientation = 0, joint = 0, ball = 0;  // terms 1-4, before `scale`
  double scale = 0;                                           // reward.scale
  float kick = 0;                                             // term 5
  // The step's reward: exactly what Step returns.
  float Total() const {
    return static_cast<float>(scale * (position + orientation + joint + ball)) + kick;
  }
};

// Terms 1-4 (and the scale) of the state in `data` against `reference` and `ball_ref`; kick 0.
RewardTerms TrackingReward(const JuggleSpec& spec, const mjData& data,
                           const CharacterPose& reference, const BallReference& ball_ref);

// Term 5 for a ball just kicked up from `cursor`'s node (REQUIRES: vertical velocity > 0): 0
// when the ball is sent to a stall (no ballistic target). A ball kicked from below the target's
// contact height is judged where it comes back down through its own height.
float KickReward(const JuggleSpec& spec, const mjData& data, const CursorState& cursor);

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_REWARD_H_
