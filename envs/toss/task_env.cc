#include "envs/toss/task_env.h"

#include <algorithm>
#include <cmath>

#include "common/status_macros.h"
#include "envs/toss/outcomes.h"
#include "envs/toss/reward.h"

namespace juggle::toss {

TossTaskEnv::TossTaskEnv(std::shared_ptr<const TossSpec> spec, Rng rng, Hand hand)
    : spec_(std::move(spec)),
      world_(spec_) {
  s_.rng = rng;
  s_.hand = hand;
  s_.mirror = TossSpec::MirrorSign(hand);
  if (spec_->toss().has_base()) base_.emplace(spec_);
}

std::unique_ptr<EnvSnapshot> TossTaskEnv::Snapshot() const {
  auto snapshot = std::make_unique<TossTaskSnapshot>();
  snapshot->spec_fingerprint = spec_->fingerprint();
  world_.Save(&snapshot->world);
  snapshot->state = s_;
  return snapshot;
}

absl::Status TossTaskEnv::Restore(const EnvSnapshot& snapshot) {
  RETURN_IF_ERROR(CheckSnapshotMatches(snapshot, spec_->family(), spec_->fingerprint()));
  const auto* task = dynamic_cast<const TossTaskSnapshot*>(&snapshot);
  if (task == nullptr) {
    return absl::InvalidArgumentError(
        "the snapshot is of another kind of toss env than the single-arm task env");
  }
  world_.Restore(task->world);
  s_ = task->state;
  return absl::OkStatus();
}

void TossTaskEnv::Reset(const AdaptiveWalk&) {
  s_.steps = 0;
  s_.completions = 0;
  s_.released = false;
  const config::TossConfig& t = spec_->toss();
  world_.Reset(&s_.rng, t.start_noise(),
               t.has_start_speed_noise() ? t.start_speed_noise() : 10 * t.start_noise());
  // No draw without recorded states: episodes of configs without them stay as they were.
  if (t.start_state_size() > 0 && s_.rng.Uniform() < t.recorded_start_fraction()) {
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
      static_cast<int>(s_.rng.UniformInt(static_cast<uint64_t>(t.start_state_size()))));
  const double noise = t.recorded_start_noise();
  TossArmState state;
  for (int j = 0; j < kTossJoints; ++j) {
    state.angle[j] = recorded.angle(j) + s_.rng.Uniform(-noise, noise);
    state.speed[j] = recorded.speed(j) + s_.rng.Uniform(-10 * noise, 10 * noise);
  }
  world_.SetArmState(s_.hand, state);
}

int TossTaskEnv::SampleThrowValue() {
  // Values whose Eq. 1 flight time is positive (1 and 2 are a handoff and a hold).
  const config::TossConfig& t = spec_->toss();
  std::vector<int> values;
  for (int n = t.min_throw(); n <= t.max_throw(); ++n) {
    if (FlightTimeEq1(n, spec_->timing()) > 0) values.push_back(n);
  }
  const int i = std::min(static_cast<int>(s_.rng.Uniform() * values.size()),
                         static_cast<int>(values.size()) - 1);
  return values[i];
}

void TossTaskEnv::ResetCatch() {
  const config::TossConfig& t = spec_->toss();
  const double g = spec_->timing().gravity;
  // Everything in the right arm's frame first, then mirrored into the world.
  const int n = SampleThrowValue();
  const double flight =
      FlightTimeEq1(n, spec_->timing()) * (1 + s_.rng.Uniform(-t.flight_jitter(), t.flight_jitter()));
  const double origin_x = n % 2 == 1 ? -t.hand_x() : t.hand_x();  // odd throws cross
  const double land_x = t.hand_x() + s_.rng.Uniform(-t.landing_spread(), t.landing_spread());
  const double vx = (land_x - origin_x) / flight, vz = g * flight / 2;
  const double arrival = std::min(s_.rng.Uniform(t.arrival_min_s(), t.arrival_max_s()), flight);
  const double since_throw = flight - arrival;
  const Vec2 position{origin_x + vx * since_throw,
                      t.hand_z() + vz * since_throw - 0.5 * g * since_throw * since_throw};
  const Vec2 velocity{vx, vz - g * since_throw};
  world_.SetFree(0, {s_.mirror * position.x, position.z}, {s_.mirror * velocity.x, velocity.z});
}

void TossTaskEnv::ResetThrow() {
  const config::TossConfig& t = spec_->toss();
  s_.throw_value = SampleThrowValue();
  const ThrowTiming timing = ComputeThrowTiming(s_.throw_value, s_.hand == Hand::kRight ? 0 : 1,
                                                spec_->timing());
  s_.target_velocity = {timing.v_x, timing.v_z};  // signed for this hand by the schedule
  const double t_throw = t.dwell_ratio() * t.hand_period_s() +
                         s_.rng.Uniform(-t.catch_timing_jitter_s(), t.catch_timing_jitter_s());
  s_.release_step = std::max(1, static_cast<int>(std::lround(t_throw / spec_->dt())));
  world_.Hold(0, s_.hand);
}

StepResult TossTaskEnv::Step(const float* action, const AdaptiveWalk&) {
  const Hand other = s_.hand == Hand::kRight ? Hand::kLeft : Hand::kRight;
  if (base_) {
    // The task's ball is ball 0; its hand catches it or throws it at release_step.
    const JointTargets targets =
        spec_->toss().task() == config::THROW
            ? base_->Throw(world_, s_.hand, std::max(1, s_.release_step - s_.steps),
                           s_.target_velocity)
            : base_->Catch(world_, s_.hand, 0, 0.0);
    world_.SetTargets(s_.hand, base_->WithResidual(s_.hand, targets, action));
    world_.SetTargets(other, base_->WithResidual(other, base_->Home(world_, other), nullptr));
  } else {
    world_.SetAction(s_.hand, action);
    world_.SetHomeTargets(other);
  }
  world_.Step();
  ++s_.steps;
  if (world_.diverged()) return {0.0f, Outcome::kDiverged};
  StepResult r = spec_->toss().task() == config::THROW ? StepThrow() : StepCatch();
  if (r.outcome == Outcome::kRunning && s_.steps >= spec_->toss().max_episode_steps()) {
    r.outcome = Outcome::kTimeLimit;
  }
  return r;
}

StepResult TossTaskEnv::StepCatch() {
  const config::TossConfig& t = spec_->toss();
  StepResult r;
  double reward = EffortReward(t, world_.Effort(s_.hand));
  if (world_.CanCatch(0, s_.hand)) {
    const double height_error = std::abs(t.hand_z() - world_.ball_position(0).z);
    world_.Hold(0, s_.hand);
    const Vec2 v = world_.palm_velocity(s_.hand);
    reward += CatchReward(t, height_error, std::hypot(v.x, v.z));
    r.outcome = kCaught;
    s_.completions = 1;
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
  double reward = EffortReward(t, world_.Effort(s_.hand));
  if (s_.steps >= s_.release_step) {
    const Vec2 p = world_.palm_position(s_.hand);
    const Vec2 v = world_.Release(0);
    const Vec2 dp{p.x - spec_->home_x(s_.hand), p.z - spec_->home_z()};
    const Vec2 dv{v.x - s_.target_velocity.x, v.z - s_.target_velocity.z};
    s_.release_position_error = std::hypot(dp.x, dp.z);
    s_.release_velocity_error = std::hypot(dv.x, dv.z);
    reward += ReleaseReward(t, dp, dv);
    if (IsGoodThrow(*spec_, s_.hand, s_.throw_value, p, v)) s_.completions = 1;
    r.outcome = kReleased;
    s_.released = true;
  }
  r.reward = static_cast<float>(reward);
  return r;
}

void TossTaskEnv::WriteObservation(float* obs) const {
  world_.WriteArmObservation(s_.hand, 0, obs);
  if (spec_->toss().task() == config::THROW) {
    obs[kTossCatchObs] = static_cast<float>((s_.release_step - s_.steps) * spec_->dt());
    obs[kTossCatchObs + 1] = static_cast<float>(s_.mirror * s_.target_velocity.x);
    obs[kTossCatchObs + 2] = static_cast<float>(s_.target_velocity.z);
  }
}

void TossTaskEnv::AppendEpisodeMetrics(std::vector<NamedValue>* out) const {
  if (!s_.released) return;
  out->push_back({"release_position_error", s_.release_position_error});
  out->push_back({"release_velocity_error", s_.release_velocity_error});
}

}  // namespace juggle::toss
