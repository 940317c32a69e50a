#include "envs/soccer_juggle/stance_change.h"

#include <algorithm>
#include <cmath>

namespace juggle::soccer_juggle {
namespace {

// The ankle body's height above the floor standing (m), where a placed foot's ankle ends.
constexpr double kAnkleHeight = 0.049;

bool IsLegSwing(const ControlGraph& graph, int node, config::Side* side) {
  const config::ReferencePose& pose = graph.node(node).spec.pose();
  if (!pose.has_leg_swing()) return false;
  *side = pose.leg_swing().side();
  return true;
}

double FollowThrough(double phase) { return std::clamp((phase - 0.5) / 0.5, 0.0, 1.0); }

}  // namespace

bool HandsStanceOver(const ControlGraph& graph, const CursorState& cursor) {
  if (cursor.next < 0 || graph.node(cursor.current).stage != config::UP) return false;
  config::Side side, next_side;
  return IsLegSwing(graph, cursor.current, &side) && IsLegSwing(graph, cursor.next, &next_side) &&
         side != next_side;
}

bool KickFollowsBothFeet(const ControlGraph& graph, const CursorState& cursor,
                         bool* next_kicks_left) {
  if (cursor.next < 0 || graph.node(cursor.current).stage != config::UP) return false;
  config::Side side, next_side;
  if (IsLegSwing(graph, cursor.current, &side) || !IsLegSwing(graph, cursor.next, &next_side)) {
    return false;
  }
  *next_kicks_left = next_side == config::LEFT;
  return true;
}

void PlaceKickingFoot(const JuggleSpec& spec, const mjData& data, bool kick_left,
                      SwingAdjust* adjust) {
  const config::StanceChange& change = spec.env().stance_change();
  const mjModel* m = spec.model();
  const int hip_body = m->dof_bodyid[spec.joint(kick_left ? kLeftHip : kRightHip).dof_adr];
  const double* com = data.subtree_com + 3 * spec.root_body();
  const double* velocity = data.qvel;  // the root's linear velocity (world frame)
  const double* hip = data.xpos + 3 * hip_body;
  const double leg = std::max(0.3, hip[2] - kAnkleHeight);
  const double x = com[0] + change.capture_s() * velocity[0];
  const double y = com[1] + change.capture_s() * velocity[1] +
                   (kick_left ? change.place_width() : -change.place_width());
  // The straight leg's angles from the vertical: forward about the root's z axis (flexion),
  // toward world +y about its x axis (docs: reference_pose.h, y-up joint frames).
  const double pitch = std::asin(std::clamp((x - hip[0]) / leg, -0.9, 0.9));
  const double roll = std::asin(std::clamp((y - hip[1]) / leg, -0.9, 0.9));
  double tilt[3];  // the pelvis's rotation from upright, in its own frame
  mju_subQuat(tilt, data.qpos + 3, kUprightQuat);
  adjust->place_hip = pitch - tilt[2];
  const double hip_roll = roll - tilt[0];  // about x: + moves a foot toward world +y
  adjust->place_abduction = kick_left ? hip_roll : -hip_roll;
}

double LeanTowardKick(const config::StanceChange& change, bool kick_left, double phase) {
  const double lean = change.lean() * FollowThrough(phase);
  return kick_left ? lean : -lean;
}

double HeaderShiftShare(const config::StanceChange& change, double phase) {
  return change.header_shift() * FollowThrough(phase);
}

double HeaderRollShare(const config::StanceChange& change, double phase) {
  return change.header_roll() * FollowThrough(phase);
}

}  // namespace juggle::soccer_juggle
