// The DeepMimic humanoid of configs/models/humanoid.xml as every family that uses it drives it
// (soccer juggling; football next, docs/football.md): its 12 actuated joints in qpos order, their
// default PD gains, their resolution against a compiled model, and the stable-PD torques
// (docs/environment.md, "Control"). Pure functions over MuJoCo's model and data.
#ifndef JUGGLE_ENVS_HUMANOID_HUMANOID_H_
#define JUGGLE_ENVS_HUMANOID_HUMANOID_H_

#include <mujoco/mujoco.h>

#include <array>
#include <cmath>
#include <string>

#include "absl/status/statusor.h"

namespace juggle::humanoid {

constexpr int kNumActuatedDofs = 28;  // 8 ball joints × 3 + 4 hinges

// The 12 actuated joints, in qpos order (reference generalized-coordinate order).
enum JointId {
  kChest = 0, kNeck, kRightShoulder, kRightElbow, kLeftShoulder, kLeftElbow,
  kRightHip, kRightKnee, kRightAnkle, kLeftHip, kLeftKnee, kLeftAnkle, kNumJoints
};
extern const char* const kJointNames[kNumJoints];

constexpr int kCharacterNq = 43;  // root 7 + 8 ball joints × 4 + 4 hinges
constexpr int kCharacterNv = 34;  // root 6 + 8 × 3 + 4
// The root's orientation standing upright and facing forward (w, x, y, z).
inline constexpr double kUprightRoot[4] = {M_SQRT1_2, M_SQRT1_2, 0, 0};

using CharacterPose = std::array<double, kCharacterNq>;

struct ActuatedJoint {
  int qpos_adr = 0;
  int dof_adr = 0;
  int dofs = 1;           // 3 for ball joints, 1 for hinges
  double kp = 0;          // N·m/rad
  double kd = 0;          // N·m·s/rad (set as joint damping: implicit in Euler)
  double torque_scale = 1;
};
using Joints = std::array<ActuatedJoint, kNumJoints>;

// The release's gains and feed-forward scales (the reference implementation's).
struct DefaultGains {
  double kp, kd, scale;
};
DefaultGains DefaultGainsFor(JointId joint);

// The joint named `name`, or −1.
int JointIdByName(const std::string& name);

// The 12 joints' addresses in `m` with their default gains. INVALID_ARGUMENT "the model has no
// joint 'x'" or "joint 'x' is out of the expected order" (the caller names its config field).
absl::StatusOr<Joints> ResolveJoints(const mjModel* m);

// Stable PD: kd as each actuated dof's joint damping, integrated implicitly by the Euler
// integrator. Call before any mjData of `m` steps.
void WriteJointDamping(const Joints& joints, mjModel* m);

// Into tau[dof] for every actuated dof: kp·(err − h·q̇) + feedforward[dof], err the reference's
// difference from the current pose (mju_subQuat for ball joints), h the model's timestep; the
// damping kd·q̇ is the joints' own (WriteJointDamping). Other entries of tau are left as they
// are. `reference` holds a kCharacterNq pose; `feedforward` and `tau` hold nv values.
void StablePdTorques(const Joints& joints, const double* reference, const mjModel* m,
                     const mjData* d, const double* feedforward, double* tau);

}  // namespace juggle::humanoid

#endif  // JUGGLE_ENVS_HUMANOID_HUMANOID_H_
