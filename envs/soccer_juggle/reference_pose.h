// Kinematic reference poses (the PD targets) of the control-graph nodes, as functions of the
// phase. Generators follow the reference implementation's (leg swing, head dip, chest lean;
// docs/control_graph.md); keyframes are authored in the config. Poses use DeepMimic's y-up joint frames (x forward, y up, z = right).
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_REFERENCE_POSE_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_REFERENCE_POSE_H_

#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {

// Sets ball joint `j` of `pose` to the rotation with rotation vector `rotvec` (rad).
void SetBallJointRotation(const JuggleSpec& spec, JointId j, const double rotvec[3],
                          CharacterPose* pose);
// Same with a single-axis rotation: axis 0 = x, 1 = y, 2 = z.
void SetBallJointAxisRotation(const JuggleSpec& spec, JointId j, int axis, double angle,
                              CharacterPose* pose);
// Sets hinge `j` to `angle` (rad).
void SetHinge(const JuggleSpec& spec, JointId j, double angle, CharacterPose* pose);

// The standing pose: root at (0, 0, height), upright-forward, every joint at the rest pose.
CharacterPose StandingPose(const JuggleSpec& spec);

// The leg a node's pose swings — a leg swing's side, or keyframes' swing_side — into `side`;
// false when both feet stand (headers, the chest, keyframes without a swing side).
bool SwingingLeg(const config::ReferencePose& pose, config::Side* side);

// Ball-dependent changes of a leg swing (env.kick_feedback, the planner's kick variables):
// added to the swing's hip flexion, knee, hip abduction and ankle amplitudes (rad) and to its
// phase; keyframes with a swing side take them too (ComputeReferencePose). Zero: the
// configured swing.
struct SwingAdjust {
  double hip = 0, knee = 0, abduction = 0, phase = 0, ankle = 0;
  // env.stance_change's foot placement (envs/soccer_juggle/stance_change.h), set while the
  // node hands the stance to the other foot: over the follow-through (φ ≥ 0.5) the kicking
  // hip's flexion and abduction blend toward place_hip and place_abduction (rad) and the knee
  // lifts the foot clear. Not placing: the configured swing.
  bool placing = false;
  // stance_roll's side (below; the snapshot tests compare the struct field by field).
  bool stance_roll_left_kick = false;
  double place_hip = 0, place_abduction = 0;
  // A header node's head feedback (NodeSpec.head_feedback): the chest's pitch and roll (rad,
  // added to a head_dip pose at every phase) that move the head under the coming ball.
  double lean_pitch = 0, lean_roll = 0;
  // Its timing: added to a head dip's phase (a share of the cycle; negative: the dip later).
  double head_phase = 0;
  // env.stance_change.header_roll (stance_change.h): the next kick's stance roll (rad, the
  // leg_swing's sign convention) added to a head_dip pose, on the standing leg of a kick with
  // the left foot if stance_roll_left_kick, else of the right foot.
  double stance_roll = 0;
};

// Writes the reference pose of `node` at phase φ into `pose` (root x, y relative to the
// episode's anchor). Deterministic and allocation-free. `adjust` changes leg swings,
// keyframes with a swing side (their phase, and the swinging leg by sin²(πφ)) and a head
// dip's lean only.
void ComputeReferencePose(const JuggleSpec& spec, int node, double phase, CharacterPose* pose,
                          const SwingAdjust& adjust = {});

// The reference pose of the cursor's node at phase φ: ComputeReferencePose, blended over the
// end of an UP node into the next node's pose at φ = 0 when the next node sets pose_lead_in
// (a smoothstep over that share of the UP half cycle). What the env tracks and the planner
// perturbs.
void ComputeCursorPose(const JuggleSpec& spec, const CursorState& cursor, double phase,
                       CharacterPose* pose, const SwingAdjust& adjust = {});

// The upright-forward root orientation (w, x, y, z) = (√½, √½, 0, 0).
extern const double kUprightQuat[4];

// sin²(θ/2) of the rotation θ between unit quaternions a and b (sign-safe: q and −q agree).
double RotationSin2(const double* a, const double* b);

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_REFERENCE_POSE_H_
