#include "envs/toss/loop_env.h"

#include <algorithm>
#include <cmath>

#include "common/status_macros.h"
#include "envs/toss/outcomes.h"
#include "envs/toss/reward.h"

namespace juggle::toss {

TossLoopEnv::TossLoopEnv(std::shared_ptr<const TossSpec> spec, Rng rng)
    : spec_(std::move(spec)), rng_(rng), failure_rate_(spec_->loop_patterns().size(), 0.0) {
  StartRun();
}

std::unique_ptr<EnvSnapshot> TossLoopEnv::Snapshot() const {
  auto snapshot = std::make_unique<TossLoopSnapshot>();
  snapshot->spec_fingerprint = spec_->fingerprint();
  snapshot->juggler = juggler_->Clone();
  snapshot->rng = rng_;
  snapshot->steps = steps_;
  snapshot->completions = completions_;
  snapshot->runs_started = runs_started_;
  snapshot->run_pattern = run_pattern_;
  snapshot->failure_rate = failure_rate_;
  return snapshot;
}

absl::Status TossLoopEnv::Restore(const EnvSnapshot& snapshot) {
  RETURN_IF_ERROR(CheckSnapshotMatches(snapshot, spec_->family(), spec_->fingerprint()));
  const auto* loop = dynamic_cast<const TossLoopSnapshot*>(&snapshot);
  if (loop == nullptr) {
    return absl::InvalidArgumentError(
        "the snapshot is of another kind of toss env than the in-loop env");
  }
  juggler_ = loop->juggler->Clone();
  rng_ = loop->rng;
  steps_ = loop->steps;
  completions_ = loop->completions;
  runs_started_ = loop->runs_started;
  run_pattern_ = loop->run_pattern;
  failure_rate_ = loop->failure_rate;
  return absl::OkStatus();
}

int TossLoopEnv::DrawPattern() {
  const config::TossLoopConfig& loop = spec_->toss().loop();
  const int n = static_cast<int>(failure_rate_.size());
  if (!loop.weight_failures()) return static_cast<int>(rng_.UniformInt(n));
  double total = 0;
  for (double r : failure_rate_) total += loop.failure_floor() + r;
  double u = rng_.Uniform(0, total);
  for (int i = 0; i < n; ++i) {
    u -= loop.failure_floor() + failure_rate_[i];
    if (u < 0) return i;
  }
  return n - 1;
}

void TossLoopEnv::StartRun() {
  const config::TossLoopConfig& loop = spec_->toss().loop();
  if (juggler_ && run_pattern_ >= 0) {
    constexpr double kAverage = 0.1;
    const bool failed = juggler_->result().end != JuggleEnd::kMaxThrows;
    failure_rate_[run_pattern_] += kAverage * ((failed ? 1.0 : 0.0) - failure_rate_[run_pattern_]);
  }
  const std::vector<Siteswap>& patterns = spec_->loop_patterns();
  run_pattern_ = DrawPattern();
  JuggleSchedule schedule(patterns[run_pattern_]);
  if (loop.transition_fraction() > 0 && rng_.Uniform(0, 1) < loop.transition_fraction()) {
    // Scored on the pattern it passes into.
    const int from = DrawPattern();
    absl::StatusOr<JuggleSchedule> t = JuggleSchedule::Transitions(
        {patterns[from], patterns[run_pattern_]}, loop.transition_throws());
    if (t.ok()) schedule = *std::move(t);
  }
  JugglerOptions options;
  options.max_throws = loop.max_throws();
  options.seed = rng_.NextU64();
  options.start_noise = loop.start_noise();
  options.ball_noise = loop.has_ball_noise() ? loop.ball_noise() : 10 * loop.start_noise();
  options.ball_speed_noise = loop.ball_speed_noise();
  // The spec validated the patterns (ball counts) when it was built.
  juggler_ = *TossJuggler::Create(spec_, schedule,
                                  TossPolicies{spec_->loop_catcher(), spec_->loop_thrower()},
                                  options);
  ++runs_started_;
}

bool TossLoopEnv::InSegment() const {
  if (TrainsThrow()) return juggler_->HoldsThrow(Hand::kRight);
  return juggler_->world().held_by(Hand::kRight) < 0 && juggler_->IncomingBall(Hand::kRight) >= 0;
}

void TossLoopEnv::Reset(const AdaptiveWalk&) {
  steps_ = 0;
  completions_ = 0;
  // Each run reaches a segment within a few beats (every pattern throws from both hands), so
  // this ends; a run that ends first is replaced.
  while (juggler_->over() || !InSegment()) {
    if (juggler_->over()) {
      StartRun();
    } else {
      juggler_->Step();
    }
  }
}

StepResult TossLoopEnv::Step(const float* action, const AdaptiveWalk&) {
  const bool running = juggler_->Step(action);
  ++steps_;
  StepResult r;
  if (!running && juggler_->result().end == JuggleEnd::kDiverged) {
    r.outcome = Outcome::kDiverged;
    return r;
  }
  const config::TossConfig& t = spec_->toss();
  const double effort = EffortReward(t, juggler_->world().Effort(Hand::kRight));
  r = TrainsThrow() ? ThrowOutcome() : CatchOutcome();
  if (r.outcome == kCaught) completions_ = 1;
  r.reward += static_cast<float>(effort);
  if (r.outcome == Outcome::kRunning && (!running || steps_ >= t.max_episode_steps())) {
    r.outcome = Outcome::kTimeLimit;  // not this segment's failure: bootstrap
  }
  return r;
}

StepResult TossLoopEnv::CatchOutcome() const {
  const config::TossConfig& t = spec_->toss();
  const HandEvents& e = juggler_->events(Hand::kRight);
  StepResult r;
  if (e.caught) {
    r.reward = static_cast<float>(CatchReward(t, e.catch_height_error, e.catch_palm_speed));
    r.outcome = kCaught;
  } else if (juggler_->over() && juggler_->end_hand() == Hand::kRight &&
             (juggler_->result().end == JuggleEnd::kDropped ||
              juggler_->result().end == JuggleEnd::kMissedBeat)) {
    r.reward = static_cast<float>(DropReward(t));
    r.outcome = kDropped;
  }
  return r;
}

StepResult TossLoopEnv::ThrowOutcome() {
  const config::TossConfig& t = spec_->toss();
  const HandEvents& e = juggler_->events(Hand::kRight);
  StepResult r;
  if (!e.released) return r;
  const Vec2 dp{e.release_position.x - spec_->home_x(Hand::kRight),
                e.release_position.z - spec_->home_z()};
  const Vec2 dv{e.release_velocity.x - e.target_velocity.x,
                e.release_velocity.z - e.target_velocity.z};
  r.reward = static_cast<float>(ReleaseReward(t, dp, dv));
  r.outcome = kReleased;
  if (e.good_throw) completions_ = 1;
  return r;
}

void TossLoopEnv::WriteObservation(float* obs) const {
  float full[kTossThrowObs];
  juggler_->WriteObservation(Hand::kRight, full);
  std::copy(full, full + spec_->obs_dim(), obs);
}

}  // namespace juggle::toss
