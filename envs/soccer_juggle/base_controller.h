// The base controller (not in the release): what the env adds each control step, from the
// character's and the ball's own state, to the policy's feed-forward torques and to the leg
// swing it tracks — so that zero action already kicks (docs/learning.md, "The base controller
// with zero action"). Three parts, each off unless its config is set:
//   - reference feed-forward (env.reference_feedforward): the inverse dynamics of the
//     reference motion, so that the PD only corrects deviations;
//   - stance balance (env.stance_balance): centre of mass over the stance ankle, pelvis upright
//     and heading, through the stance leg of a leg-swing node, through both legs elsewhere;
//   - kick feedback (env.kick_feedback): the leg swing moved with the ball's predicted crossing
//     of the contact height;
//   - head feedback (a header node's head_feedback): the chest leans the head under the coming
//     ball, placed so that the bounce returns the ball to the target;
//   - stance change (env.stance_change, stance_change.h): the last kick before the other
//     foot's puts its foot down beside the body and leans onto it; a header before a kick
//     moves the body over the kick's standing foot.
// Holds no episode state (the swing change lives in JuggleEnvState): only a scratch mjData.
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_BASE_CONTROLLER_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_BASE_CONTROLLER_H_

#include <mujoco/mujoco.h>

#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/graph_cursor.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {

class BaseController {
 public:
  // REQUIRES: `spec` outlives the controller.
  explicit BaseController(const JuggleSpec& spec);

  // env.kick_feedback: recomputes `*adjust` from the ball's free flight while the cursor's
  // DOWN node swings a leg (a leg swing, or keyframes with a swing side), has not touched the
  // ball (`kick_touched` false) and the ball is above the contact height; leaves it otherwise
  // (held after the contact until the next DOWN node).
  // env.stance_change: sets adjust->placing, and the placement while it is set, every step;
  // adjust->stance_roll (header_roll) in a header's UP node before a kick, every step.
  void UpdateSwingAdjust(const mjData& data, const CursorState& cursor, bool kick_touched,
                         SwingAdjust* adjust) const;

  // Adds to `feedforward` ([kCharacterNv], N·m) env.reference_feedforward × the inverse
  // dynamics of the reference around the cursor's phase (`reference`: the pose at that phase,
  // changed by `adjust`) and env.stance_balance's torques, each balance term clamped to its
  // joint's feed-forward range. Updates `data`'s subtree velocities (mj_subtreeVel).
  void AddFeedforward(const CursorState& cursor, const CharacterPose& reference,
                      const SwingAdjust& adjust, mjData* data, double* feedforward);

 private:
  // A header node's head feedback (NodeSpec.head_feedback): sets adjust->lean_pitch and
  // lean_roll from the ball's free flight toward the contact height — in a DOWN node until the
  // touch, in an UP node toward the next crossing if the next node is a header with a head
  // feedback (else upright); holds them while the ball is below the contact height and falling.
  void UpdateHeadLean(const mjData& data, const CursorState& cursor, bool kick_touched,
                      SwingAdjust* adjust) const;
  // The phase change (a share of the cycle) that makes a pose follow a ball crossing the
  // contact height `crossing_s` from now, × `gain`: negative (later) for a ball later than
  // the cursor's nominal contact. REQUIRES: cursor.phase_speed > 0.
  double TimingShift(const CursorState& cursor, double crossing_s, double gain) const;
  void AddReferenceFeedforward(const CursorState& cursor, const CharacterPose& reference,
                               const SwingAdjust& adjust, const mjData& data,
                               double* feedforward);
  // `adjust`: the step's; its `placing` leans the balance onto the foot put down.
  void AddStanceBalance(const CursorState& cursor, const SwingAdjust& adjust, mjData* data,
                        double* feedforward) const;
  const double* AnklePosition(const mjData& data, humanoid::JointId ankle) const;

  const JuggleSpec& spec_;
  const mjModel* model_;
  MjDataPtr id_data_;  // scratch of the inverse dynamics; null when reference_feedforward is 0
};

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_BASE_CONTROLLER_H_
