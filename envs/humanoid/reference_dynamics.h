// The joint torques that make the humanoid follow a reference motion (issue 14's reference
// feed-forward; docs/learning.md, "The base controller with zero action"): inverse dynamics of
// the reference's pose, velocity and acceleration by central differences, with the character
// lifted out of contact and its root held still, so the stable PD only corrects deviations.
// Used by soccer juggling's base controller and football's kick. Pure function over MuJoCo's
// model and a scratch mjData.
#ifndef JUGGLE_ENVS_HUMANOID_REFERENCE_DYNAMICS_H_
#define JUGGLE_ENVS_HUMANOID_REFERENCE_DYNAMICS_H_

#include <mujoco/mujoco.h>

#include "envs/humanoid/humanoid.h"

namespace juggle::humanoid {

// Writes into tau[dof] for every actuated dof the torque of following the reference through
// `now` (its poses `dt` seconds before and after: `before`, `after`): mj_inverse's force plus
// the stable PD's own drag kp·h·q̇ (which the PD would otherwise subtract). The character is
// lifted 100 m and its root and every dof after the character's (a ball's) are held still;
// their entries of tau are left as they are. `data` supplies the other bodies' positions.
// `scratch`: an mjData of `m` (overwritten).
void ReferenceInverseDynamics(const Joints& joints, const mjModel* m, const mjData& data,
                              const CharacterPose& before, const CharacterPose& now,
                              const CharacterPose& after, double dt, mjData* scratch,
                              double* tau);

}  // namespace juggle::humanoid

#endif  // JUGGLE_ENVS_HUMANOID_REFERENCE_DYNAMICS_H_
