#include "envs/toss/base_controller.h"

#include <algorithm>
#include <cmath>

#include "envs/ballistic.h"
#include "envs/toss/arm_tracking.h"

namespace juggle::toss {
namespace {

Hand Other(Hand h) { return h == Hand::kRight ? Hand::kLeft : Hand::kRight; }

ArmAngles WithoutNeck(const std::array<double, kTossJoints>& a) { return {a[1], a[2], a[3]}; }

}  // namespace

TossBaseController::TossBaseController(std::shared_ptr<const TossSpec> spec)
    : spec_(std::move(spec)), geometry_(ReadArmGeometry(*spec_)) {
  home_ = WithoutNeck(spec_->home());
  home_hand_angle_ = HandAngle(home_);
}

Vec2 TossBaseController::ReleaseVelocity(Hand thrower, int value, double wind_accel) const {
  const double t = FlightTimeEq1(value, spec_->timing());
  const Hand catcher = value % 2 == 1 ? Other(thrower) : thrower;
  const double dx = spec_->home_x(catcher) - spec_->home_x(thrower);
  return {(dx - 0.5 * wind_accel * t * t) / t, 0.5 * spec_->timing().gravity * t};
}

JointTargets TossBaseController::Reach(const TossWorld& world, Hand hand, const ArmAngles& q_goal,
                                       const ArmAngles& v_goal, int steps) const {
  const TossArmState s = world.ArmState(hand);
  const ArmAngles q = WithoutNeck(s.angle), v = WithoutNeck(s.speed);
  ArmAngles qacc = FirstPlannedAcceleration(q, v, q_goal, v_goal, std::max(steps, 1), spec_->dt());
  const ArmAngles t = TargetsForAcceleration(world, hand, qacc);
  return {TossSpec::MirrorSign(hand) * spec_->home()[0], t[0], t[1], t[2]};
}

JointTargets TossBaseController::Throw(const TossWorld& world, Hand hand, int steps,
                                       Vec2 velocity) const {
  const double mirror = TossSpec::MirrorSign(hand);
  const Vec2 v_right{mirror * velocity.x, velocity.z};
  ArmAngles v_goal = JointSpeedsFor(geometry_, home_, v_right, spec_->toss().base().wrist_weight());
  ArmAngles q_goal = home_;
  if (steps <= 1) {
    // Only the speeds can still be set: meet the palm velocity where the arm will be.
    const TossArmState s = world.ArmState(hand);
    for (int iter = 0; iter < 3; ++iter) {
      ArmAngles q_next{};
      for (int j = 0; j < 3; ++j) q_next[j] = s.angle[j + 1] + spec_->dt() * v_goal[j];
      v_goal = JointSpeedsFor(geometry_, q_next, v_right, spec_->toss().base().wrist_weight());
      q_goal = q_next;
    }
  }
  return Reach(world, hand, q_goal, v_goal, steps);
}

JointTargets TossBaseController::Rest(const TossWorld& world, Hand hand, Vec2 palm,
                                      int steps) const {
  // Out of reach: the nearest reachable point on the way back to the home point.
  const Vec2 home{spec_->toss().hand_x(), spec_->home_z()};
  const Vec2 p_right{TossSpec::MirrorSign(hand) * palm.x, palm.z};
  std::optional<ArmAngles> q;
  constexpr int kTries = 50;
  for (int i = 0; i <= kTries && !q; ++i) {
    const double f = 1.0 - static_cast<double>(i) / kTries;
    q = SolveArmIk(geometry_, {home.x + f * (p_right.x - home.x), home.z + f * (p_right.z - home.z)},
                   home_hand_angle_);
  }
  return Reach(world, hand, q ? *q : home_, ArmAngles{}, steps);
}

JointTargets TossBaseController::Home(const TossWorld& world, Hand hand) const {
  const int settle = static_cast<int>(std::lround(spec_->toss().base().settle_s() / spec_->dt()));
  return Reach(world, hand, home_, ArmAngles{}, settle);
}

JointTargets TossBaseController::Catch(const TossWorld& world, Hand hand, int ball,
                                       double wind_accel) const {
  if (ball < 0) return Home(world, hand);
  const Vec2 p = world.ball_position(ball), v = world.ball_velocity(ball);
  const double z = spec_->home_z();
  const double t = SecondsToFall(v.z, p.z - z, spec_->timing().gravity);
  if (!(t >= 0)) return Home(world, hand);
  const double reach = spec_->toss().base().max_reach_x();
  const double x = std::clamp(p.x + v.x * t + 0.5 * wind_accel * t * t,
                              spec_->home_x(hand) - reach, spec_->home_x(hand) + reach);
  const int steps = static_cast<int>(
      std::floor((t - spec_->toss().base().catch_lead_s()) / spec_->dt()));
  return Rest(world, hand, {x, z}, std::max(steps, 1));
}

JointTargets TossBaseController::WithResidual(Hand hand, JointTargets targets,
                                              const float* action) const {
  const double mirror = TossSpec::MirrorSign(hand);
  const double scale = spec_->toss().base().residual_scale();
  const double limit = spec_->toss().base().target_limit();
  for (int j = 0; j < kTossJoints; ++j) {
    if (action != nullptr) {
      targets[j] += mirror * scale * std::clamp(static_cast<double>(action[j]), -1.0, 1.0);
    }
    const double home = mirror * spec_->home()[j];
    targets[j] = std::clamp(targets[j], home - limit, home + limit);
  }
  return targets;
}

void WindEstimator::BeforeStep(const TossWorld& world) {
  for (int b = 0; b < kTossBalls; ++b) {
    was_free_[b] = world.mode(b) == BallMode::kFree;
    vx_[b] = world.ball_velocity(b).x;
  }
}

void WindEstimator::AfterStep(const TossWorld& world) {
  double sum = 0;
  int n = 0;
  for (int b = 0; b < kTossBalls; ++b) {
    if (was_free_[b] && world.mode(b) == BallMode::kFree) {
      sum += world.ball_velocity(b).x - vx_[b];
      ++n;
    }
  }
  if (n > 0) accel_ = sum / (n * world.spec().dt());
}

}  // namespace juggle::toss
