// Stance balance of the humanoid standing on one foot (not in the release; docs/learning.md,
// "The base controller with zero action"): feed-forward torques that keep the centre of mass
// over the stance ankle (through that ankle) and the pelvis upright and heading forward
// (through that hip). Used by soccer juggling's leg-swing nodes and football's kick. Pure
// function over MuJoCo's model and data.
#ifndef JUGGLE_ENVS_HUMANOID_STANCE_BALANCE_H_
#define JUGGLE_ENVS_HUMANOID_STANCE_BALANCE_H_

#include <mujoco/mujoco.h>

#include "envs/humanoid/humanoid.h"
#include "proto/envs/soccer_juggle.pb.h"

namespace juggle::humanoid {

enum class Foot { kLeft, kRight };

// The heading (rad, about the world's vertical, 0 along +x) of a body of the character from its
// world rotation matrix (mjData::xmat, row-major): where its local x axis points, which is the
// character's forward for the root and, standing at rest, for every leg body.
double Heading(const double* xmat);

// Adds `gains`' torques for standing on `stance` to `feedforward` ([kCharacterNv], N·m), each
// term clamped to its joint's feed-forward range (action_torque × the joint's scale), as a
// policy action would be. `root_body`: the character's root body. Updates `data`'s subtree
// velocities (mj_subtreeVel) when the centre-of-mass gains are set.
void AddStanceBalance(const Joints& joints, const config::StanceBalance& gains, Foot stance,
                      int root_body, double action_torque, const mjModel* m, mjData* data,
                      double* feedforward);

// Standing on both feet: the same torques with the centre of mass held (com_x, com_y) from the
// midpoint of the two ankles, half of each gain through each ankle and each hip (so the total
// equals one stance's). Used by football's TRAP_KICK while both feet are down.
void AddDoubleStanceBalance(const Joints& joints, const config::StanceBalance& gains,
                            int root_body, double action_torque, const mjModel* m, mjData* data,
                            double* feedforward);

}  // namespace juggle::humanoid

#endif  // JUGGLE_ENVS_HUMANOID_STANCE_BALANCE_H_
