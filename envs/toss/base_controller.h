// The toss arms' base controllers (TossConfig.base; docs/toss.md, "Base controllers"). Each
// returns world-frame PD targets for one arm (𝒥 order, the neck at home) for the next Step;
// policies, when present, add residuals to them (TossJuggler, the task and loop envs).
//   Throw: the palm must leave the home point after `steps` steps at the release velocity; the
//     goal joint state is the home pose moving at the least-norm joint speeds for that palm
//     velocity, reached by the minimum-effort discrete plan (envs/toss/arm_tracking.h),
//     replanned every step. On the last step the goal speeds are taken at the configuration the
//     arm will actually have, so the palm velocity is met there.
//   Catch: the incoming ball's crossing of hand height is predicted (gravity and the estimated
//     wind); the hand plans to be there at rest catch_lead_s before the ball, replanned every
//     step (this also brakes a follow-through). No ball: home at rest within settle_s.
// Thread-compatible; one controller can serve both arms and many worlds of its spec.
#ifndef JUGGLE_ENVS_TOSS_BASE_CONTROLLER_H_
#define JUGGLE_ENVS_TOSS_BASE_CONTROLLER_H_

#include <array>
#include <memory>

#include "envs/toss/arm_kinematics.h"
#include "envs/toss/dims.h"
#include "envs/toss/world.h"

namespace juggle::toss {

using JointTargets = std::array<double, kTossJoints>;

class TossBaseController {
 public:
  // Uses spec.toss().base() (its defaults when the block is absent).
  explicit TossBaseController(std::shared_ptr<const TossSpec> spec);

  // The release velocity (world frame) for a throw of `value` from `thrower`'s home point to
  // the catching hand's home point in Eq. 1's flight time, under horizontal acceleration
  // `wind_accel` (m/s²) on the ball: v_x = (Δx − ½·a·T²)/T, v_z = g·T/2.
  Vec2 ReleaseVelocity(Hand thrower, int value, double wind_accel) const;

  // Targets that release from the home point at `velocity` (world frame) after `steps` ≥ 1 steps.
  JointTargets Throw(const TossWorld& world, Hand hand, int steps, Vec2 velocity) const;
  // Targets that catch free ball `ball` at rest; ball < 0 (or a ball that will not come down
  // through hand height): home at rest.
  JointTargets Catch(const TossWorld& world, Hand hand, int ball, double wind_accel) const;
  // Targets that bring the palm to `palm` (world frame) at rest after `steps` ≥ 1 steps.
  JointTargets Rest(const TossWorld& world, Hand hand, Vec2 palm, int steps) const;
  JointTargets Home(const TossWorld& world, Hand hand) const;

  // Adds residual_scale · clamp(action, −1, 1) (right arm's frame) to `targets` and keeps them
  // within home ± target_limit. action == nullptr: the clamp only.
  JointTargets WithResidual(Hand hand, JointTargets targets, const float* action) const;

  const ArmGeometry& geometry() const { return geometry_; }

 private:
  JointTargets Reach(const TossWorld& world, Hand hand, const ArmAngles& q_goal,
                     const ArmAngles& v_goal, int steps) const;

  std::shared_ptr<const TossSpec> spec_;
  ArmGeometry geometry_;
  ArmAngles home_{};       // shoulder, elbow, wrist of the home pose (right arm)
  double home_hand_angle_ = 0;
};

// Wind estimate for the base controllers: the free balls' mean horizontal acceleration over the
// last Step (m/s²), kept from the last Step that had a ball free before and after it.
class WindEstimator {
 public:
  // Call before world.Step().
  void BeforeStep(const TossWorld& world);
  // Call after world.Step().
  void AfterStep(const TossWorld& world);
  double accel() const { return accel_; }

 private:
  std::array<bool, kTossBalls> was_free_{};
  std::array<double, kTossBalls> vx_{};
  double accel_ = 0;
};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_BASE_CONTROLLER_H_
