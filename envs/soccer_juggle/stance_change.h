// Changing the standing foot (EnvConfig.stance_change, proto/envs/soccer_juggle.proto): which
// control steps hand the stance from one foot to the other, where the kicking foot is put down,
// and how far the balance's centre-of-mass target leans. Pure functions over the graph, the
// cursor and MuJoCo's data; the base controller (base_controller.h) and the leg swing
// (reference_pose.cc) apply them.
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_STANCE_CHANGE_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_STANCE_CHANGE_H_

#include <mujoco/mujoco.h>

#include "envs/soccer_juggle/graph_cursor.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {

// True while the cursor's node is a leg-swing UP node whose next node is the other foot's leg
// swing: the last kick before the stance changes feet.
bool HandsStanceOver(const ControlGraph& graph, const CursorState& cursor);

// True while the cursor's node is an UP node without a leg swing (a header, a chest touch)
// whose next node is a leg swing; `*next_kicks_left` is then that swing's side.
bool KickFollowsBothFeet(const ControlGraph& graph, const CursorState& cursor,
                         bool* next_kicks_left);

// Where the kicking foot should come down (stance_change.place_width, capture_s): the hip
// flexion and the abduction (rad, outward positive, SwingAdjust::place_hip and
// place_abduction) that put a straight leg from the kicking hip at COM + capture_s · v, moved
// place_width to the kicking side, for the pelvis's current tilt. Small-angle composition of
// the pelvis's and the hip's rotations; the reach is clamped to 0.9 of the leg.
void PlaceKickingFoot(const JuggleSpec& spec, const mjData& data, bool kick_left,
                      SwingAdjust* adjust);

// The stance balance's centre-of-mass target shift (m, world y) at phase φ of a node that hands
// the stance over: stance_change.lean toward the kicking side, growing linearly over φ 0.5 → 1;
// 0 before the contact.
double LeanTowardKick(const config::StanceChange& change, bool kick_left, double phase);

// The share (0 → header_shift, linear over φ 0.5 → 1) of the way from the ankles' midpoint to
// the next kick's standing ankle for the two-foot balance's target; 0 before φ 0.5.
double HeaderShiftShare(const config::StanceChange& change, double phase);

// The share (0 → header_roll, linear over φ 0.5 → 1) of the next swing's stance roll that a
// header's UP node before a kick adds to its pose; 0 before φ 0.5.
double HeaderRollShare(const config::StanceChange& change, double phase);

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_STANCE_CHANGE_H_
