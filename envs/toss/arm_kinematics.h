// Planar kinematics of one toss arm (shoulder, elbow, wrist hinges about y) in the right arm's
// frame (docs/toss.md: the left arm is its mirror image): palm position, its Jacobian, inverse
// kinematics for a palm point and hand angle, and a joint velocity for a palm velocity. The
// geometry is read from the compiled model, so a changed MJCF changes it too; a test checks it
// against MuJoCo's forward kinematics and site Jacobian. Pure functions on values; thread-safe.
#ifndef JUGGLE_ENVS_TOSS_ARM_KINEMATICS_H_
#define JUGGLE_ENVS_TOSS_ARM_KINEMATICS_H_

#include <array>
#include <optional>

#include "envs/toss/spec.h"
#include "envs/toss/world.h"

namespace juggle::toss {

// Shoulder, elbow, wrist angles (rad) or speeds: the arm's 𝒥 without the neck.
using ArmAngles = std::array<double, 3>;

struct ArmGeometry {
  Vec2 shoulder;                 // the shoulder hinge's anchor (right arm, world x–z)
  std::array<double, 3> length{};  // shoulder→elbow, elbow→wrist, wrist→palm (m)
  double elbow_sign = 1;         // sign of the home pose's elbow angle (the elbow points out)
};

// The right arm's geometry at qpos 0 (every link hanging straight down).
ArmGeometry ReadArmGeometry(const TossSpec& spec);

Vec2 PalmPosition(const ArmGeometry& g, const ArmAngles& q);
// ∂palm/∂q: row 0 is x, row 1 is z.
std::array<ArmAngles, 2> PalmJacobian(const ArmGeometry& g, const ArmAngles& q);
// The absolute angle of the hand link: shoulder + elbow + wrist.
inline double HandAngle(const ArmAngles& q) { return q[0] + q[1] + q[2]; }

// Angles that put the palm at `palm` with the hand link at absolute angle `hand_angle`, the
// elbow bent to the home pose's side; nullopt when the wrist point is out of reach.
std::optional<ArmAngles> SolveArmIk(const ArmGeometry& g, Vec2 palm, double hand_angle);

// The joint speeds of least weighted norm Σ w_j·q̇_j² that move the palm at `palm_velocity`
// in configuration `q` (the wrist gets weight `wrist_weight`, the others 1).
ArmAngles JointSpeedsFor(const ArmGeometry& g, const ArmAngles& q, Vec2 palm_velocity,
                         double wrist_weight);

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_ARM_KINEMATICS_H_
