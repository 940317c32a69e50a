// A change of the humanoid's PD target as the feed-forward torque that makes the same change of
// the PD's pull, in the policy's action units: kp × (to − from) per joint and axis (mju_subQuat
// for ball joints), divided by the action's torque unit and the joint's scale. So a planner can
// move a reference (a kick's swing) through actions a policy could produce, and its labels stay
// exact. Joints whose feed-forward scale is 0 ignore actions and get nothing. Pure function.
#ifndef JUGGLE_PLANNER_POSE_ACTION_H_
#define JUGGLE_PLANNER_POSE_ACTION_H_

#include "envs/humanoid/humanoid.h"

namespace juggle::planner {

// Adds the action of the change `from` → `to` to `out` (kNumActuatedDofs values).
void AddPoseChangeAction(const humanoid::Joints& joints, const humanoid::CharacterPose& from,
                         const humanoid::CharacterPose& to, double action_torque, double* out);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_POSE_ACTION_H_
