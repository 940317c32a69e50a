// Poses of the humanoid (envs/humanoid/humanoid.h) as PD targets: joint rotations written into
// a CharacterPose, the release's rest pose, and a config's JointRotation applied with its
// checks. Shared by soccer juggling's reference poses and football's kick. Pure functions.
#ifndef JUGGLE_ENVS_HUMANOID_POSE_H_
#define JUGGLE_ENVS_HUMANOID_POSE_H_

#include <string>

#include "absl/status/status.h"
#include "envs/humanoid/humanoid.h"
#include "proto/control_graph.pb.h"

namespace juggle::humanoid {

// Sets ball joint `j` of `pose` to the rotation with rotation vector `rotvec` (rad).
void SetBallJointRotation(const Joints& joints, JointId j, const double rotvec[3],
                          CharacterPose* pose);
// Sets hinge `j` to `angle` (rad).
void SetHinge(const Joints& joints, JointId j, double angle, CharacterPose* pose);

// The release's rest pose of the joints: identity rotations, elbows bent 1.57 rad, shoulders
// abducted 0.7 rad about x; the root's entries zero.
CharacterPose ReleaseRestPose(const Joints& joints);

// Applies `rotation` to `pose`. INVALID_ARGUMENT "unknown joint 'x'" (field "joint") or
// "joint 'x' takes N value(s), got M" (field "value"); `*field` names the field at fault.
absl::Status ApplyJointRotation(const Joints& joints, const config::JointRotation& rotation,
                                CharacterPose* pose, std::string* field);

}  // namespace juggle::humanoid

#endif  // JUGGLE_ENVS_HUMANOID_POSE_H_
