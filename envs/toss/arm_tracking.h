// Joint-space tracking for the toss arms' base controllers (envs/toss/base_controller.h):
// a minimum-effort plan in the simulator's own discrete time to a joint state a given number of
// steps ahead, and the PD targets that give an arm a chosen joint acceleration in the next Step
// (inverse dynamics through MuJoCo's mass matrix and bias forces, with the implicit joint
// damping and the held ball's weight that TossWorld::Step applies). Thread-compatible.
#ifndef JUGGLE_ENVS_TOSS_ARM_TRACKING_H_
#define JUGGLE_ENVS_TOSS_ARM_TRACKING_H_

#include "envs/toss/arm_kinematics.h"
#include "envs/toss/world.h"

namespace juggle::toss {

// Semi-implicit Euler steps of length h (v ← v + h·a, q ← q + h·v) from (q, v) reach
// (q_goal, v_goal) after `steps` steps with the accelerations a_0..a_{steps−1} of least Σ a²
// (per joint: a linear ramp, the discrete cubic); returns a_0. With steps == 1 only the
// velocity can be met: a_0 = (v_goal − v)/h. REQUIRES: steps ≥ 1, h > 0.
ArmAngles FirstPlannedAcceleration(const ArmAngles& q, const ArmAngles& v, const ArmAngles& q_goal,
                                   const ArmAngles& v_goal, int steps, double h);

// World-frame PD targets of `hand`'s shoulder, elbow and wrist under which the next
// TossWorld::Step accelerates them by `qacc` (right arm's frame), from the world's current
// state: τ = (M + h·D)·q̈ + D·ω + bias − (held ball's weight), θ̄ = θ + h·ω + τ/kp.
// Exact while no joint limit is active. REQUIRES: the world's kinematics are current (true
// after Reset, SetArmState and Step).
ArmAngles TargetsForAcceleration(const TossWorld& world, Hand hand, const ArmAngles& qacc);

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_ARM_TRACKING_H_
