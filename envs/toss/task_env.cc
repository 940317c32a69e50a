#include "envs/toss/task_env.h"

#include <algorithm>
#include <cmath>

#include "envs/toss/outcomes.h"
#include "envs/toss/reward.h"

namespace juggle::toss {

TossTaskEnv::TossTaskEnv(std::shared_ptr<const TossSpec> spec, Rng rng, Hand hand)
    : spec_(std::move(spec)),
      world_(spec_),
      rng_(rng),
      hand_(hand),
      mirror_(TossSpec::MirrorSign(hand)) {}

void TossTaskEnv::Reset(const AdaptiveWalk&) {
  steps_ = 0;
  completions_ = 0;
  released_ = false;
  const config::TossConfig& t = spec_->toss();
  world_.Reset(&rng_, t.start_noise(),
               t.has_start_speed_noise() ? t.start_speed_noise() : 10 * t.start_noise());
  // No draw without recorded states: episodes of configs without them stay as they were.
  if (t.start_state_size() > 0 && rng_.Uniform() < t.recorded_start_fraction()) {
    StartFromRecordedState();
  }
  if (t.task() == config::THROW) {
    ResetThrow();
  } else {
    ResetCatch();
  }
}

void TossTaskEnv::StartFromRecordedState() {
  const config::TossConfig& t = spec_->toss();
  const config::TossArmState& recorded = t.start_state(
      static_cast<int>(rng_.UniformInt(static_cast<uint64_t>(t.start_state_size()))));
  const double noise = t.recorded_start_noise();
  TossArmState state;
  for (int j = 0; j < kTossJoints; ++j) {
    state.angle[j] = recorded.angle(j) + rng_.Uniform(-noise, noise);
    state.speed[j] = recorded.speed(j) + rng_.Uniform(-10 * noise, 10 * noise);
  }
  world_.SetArmState(hand_, state);
}

int TossTaskEnv::SampleThrowValue() {
  // Values whose Eq. 1 flight time is positive (1 and 2 are a handoff and a hold).
  const config::TossConfig& t = spec_->toss();
  std::vector<int> values;
  for (int n = t.min_throw(); n <= t.max_throw(); ++n) {
    if (FlightTimeEq1(n, spec_->timing()) > 0) values.push_back(n);
  }
  const int i = std::min(static_cast<int>(rng_.Uniform() * values.size()),
                         static_cast<int>(values.size()) - 1);
  return values[i];
}

void TossTaskEnv::ResetCatch() {
  const config::TossConfig& t = spec_->toss();
  const double g = spec_->timing().gravity;
  // Everything in the right arm's frame first, then mirrored into the world.
  const int n = SampleThrowValue();
  const double flight =
      FlightTimeEq1(n, spec_->timing()) * (1 + rng_.Uniform(-t.flight_jitter(), t.flight_jitter()));
  const double origin_x = n % 2 == 1 ? -t.hand_x() : t.hand_x();  // odd throws cross
  const double land_x = t.hand_x() + rng_.Uniform(-t.landing_spread(), t.landing_spread());
  const double vx = (land_x - origin_x) / flight, vz = g * flight / 2;
  const double arrival = std::min(rng_.Uniform(t.arrival_min_s(), t.arrival_max_s()), flight);
  const double since_throw = flight - arrival;
  const Vec2 position{origin_x + vx * since_throw,
                      t.hand_z() + vz * since_throw - 0.5 * g * since_throw * since_throw};
  const Vec2 velocity{vx, vz - g * since_throw};
  world_.SetFree(0, {mirror_ * position.x, position.z}, {mirror_ * velocity.x, velocity.z});
}

void TossTaskEnv::ResetThrow() {
  const config::TossConfig& t = spec_->toss();
  throw_value_ = SampleThrowValue();
  const ThrowTiming timing = ComputeThrowTiming(throw_value_, hand_ == Hand::kRight ? 0 : 1,
                                                spec_->timing());
  target_velocity_ = {timing.v_x, timing.v_z};  // signed for this hand by the schedule
  const double t_throw = t.dwell_ratio() * t.hand_period_s() +
                         rng_.Uniform(-t.catch_timing_jitter_s(), t.catch_timing_jitter_s());
  release_step_ = std::max(1, static_cast<int>(std::lround(t_throw / spec_->dt())));
  world_.Hold(0, hand_);
}

StepResult TossTaskEnv::Step(const float* action, const AdaptiveWalk&) {
  world_.SetAction(hand_, action);
  world_.SetHomeTargets(hand_ == Hand::kRight ? Hand::kLeft : Hand::kRight);
  world_.Step();
  ++steps_;
  if (world_.diverged()) return {0.0f, Outcome::kDiverged};
  StepResult r = spec_->toss().task() == config::THROW ? StepThrow() : StepCatch();
  if (r.outcome == Outcome::kRunning && steps_ >= spec_->toss().max_episode_steps()) {
    r.outcome = Outcome::kTimeLimit;
  }
  return r;
}

StepResult TossTaskEnv::StepCatch() {
  const config::TossConfig& t = spec_->toss();
  StepResult r;
  double reward = EffortReward(t, world_.Effort(hand_));
  if (world_.CanCatch(0, hand_)) {
    const double height_error = std::abs(t.hand_z() - world_.ball_position(0).z);
    world_.Hold(0, hand_);
    reward += CatchReward(t, height_error);
    r.outcome = kCaught;
    completions_ = 1;
  } else if (world_.ball_position(0).z < t.drop_z()) {
    reward += DropReward(t);
    r.outcome = kDropped;
  }
  r.reward = static_cast<float>(reward);
  return r;
}

StepResult TossTaskEnv::StepThrow() {
  const config::TossConfig& t = spec_->toss();
  StepResult r;
  double reward = EffortReward(t, world_.Effort(hand_));
  if (steps_ >= release_step_) {
    const Vec2 p = world_.palm_position(hand_);
    const Vec2 v = world_.Release(0);
    const Vec2 dp{p.x - spec_->home_x(hand_), p.z - spec_->home_z()};
    const Vec2 dv{v.x - target_velocity_.x, v.z - target_velocity_.z};
    release_position_error_ = std::hypot(dp.x, dp.z);
    release_velocity_error_ = std::hypot(dv.x, dv.z);
    reward += ReleaseReward(t, dp, dv);
    if (IsGoodThrow(*spec_, hand_, throw_value_, p, v)) completions_ = 1;
    r.outcome = kReleased;
    released_ = true;
  }
  r.reward = static_cast<float>(reward);
  return r;
}

void TossTaskEnv::WriteObservation(float* obs) const {
  world_.WriteArmObservation(hand_, 0, obs);
  if (spec_->toss().task() == config::THROW) {
    obs[kTossCatchObs] = static_cast<float>((release_step_ - steps_) * spec_->dt());
    obs[kTossCatchObs + 1] = static_cast<float>(mirror_ * target_velocity_.x);
    obs[kTossCatchObs + 2] = static_cast<float>(target_velocity_.z);
  }
}

void TossTaskEnv::AppendEpisodeMetrics(std::vector<NamedValue>* out) const {
  if (!released_) return;
  out->push_back({"release_position_error", release_position_error_});
  out->push_back({"release_velocity_error", release_velocity_error_});
}

}  // namespace juggle::toss
