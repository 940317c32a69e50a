#include "envs/toss/juggler.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace juggle::toss {
namespace {

Hand Other(Hand h) { return h == Hand::kRight ? Hand::kLeft : Hand::kRight; }
Hand BeatHand(int beat) { return ((beat % 2) + 2) % 2 == 0 ? Hand::kRight : Hand::kLeft; }

}  // namespace

const char* JuggleEndName(JuggleEnd end) {
  switch (end) {
    case JuggleEnd::kMaxThrows: return "max_throws";
    case JuggleEnd::kDropped: return "dropped";
    case JuggleEnd::kMissedBeat: return "missed_beat";
    case JuggleEnd::kDiverged: return "diverged";
  }
  return "unknown";
}

absl::StatusOr<std::unique_ptr<TossJuggler>> TossJuggler::Create(
    std::shared_ptr<const TossSpec> spec, const Siteswap& pattern, TossPolicies policies,
    JugglerOptions options) {
  return Create(std::move(spec), JuggleSchedule(pattern), policies, options);
}

absl::StatusOr<std::unique_ptr<TossJuggler>> TossJuggler::Create(
    std::shared_ptr<const TossSpec> spec, const JuggleSchedule& schedule, TossPolicies policies,
    JugglerOptions options) {
  if (schedule.first().balls() < 1 || schedule.max_balls() > kTossBalls) {
    return absl::InvalidArgumentError(absl::StrCat(schedule.Name(), " has ", schedule.max_balls(),
                                                   " balls; the toss model juggles 1 to ",
                                                   kTossBalls));
  }
  if (options.max_throws < 1) return absl::InvalidArgumentError("max_throws must be >= 1");
  return std::unique_ptr<TossJuggler>(
      new TossJuggler(std::move(spec), schedule, policies, options));
}

TossJuggler::TossJuggler(std::shared_ptr<const TossSpec> spec, const JuggleSchedule& schedule,
                         TossPolicies policies, JugglerOptions options)
    : spec_(std::move(spec)),
      schedule_(schedule),
      policies_(policies),
      options_(options),
      world_(spec_) {
  if (spec_->toss().has_base()) base_.emplace(spec_);
  Rng rng = Rng::ForStream(options_.seed, 0, 0);
  world_.Reset(&rng, options_.start_noise, 10 * options_.start_noise);
  PlaceInitialBalls(&rng);
}

int TossJuggler::Value(int beat) const { return schedule_.At(beat).value; }

absl::StatusOr<int> TossJuggler::SwitchPattern(const Siteswap& next) {
  if (over_) return absl::FailedPreconditionError("the run is over");
  if (next.balls() < 1 || next.balls() > kTossBalls) {
    return absl::InvalidArgumentError(absl::StrCat(next.ToString(), " has ", next.balls(),
                                                   " balls; the model has 1 to ", kTossBalls));
  }
  const int beat = std::max(std::max(next_beat_, next_add_beat_), 0);
  absl::StatusOr<JuggleSchedule> switched = schedule_.SwitchAt(beat, next);
  if (!switched.ok()) return switched.status();
  if (switched->max_balls() > kTossBalls) {
    return absl::InvalidArgumentError(absl::StrCat("the passage to ", next.ToString(),
                                                   " needs more balls than the model has"));
  }
  schedule_ = *std::move(switched);
  return beat;
}

int TossJuggler::DwellSteps() const {
  const config::TossConfig& t = spec_->toss();
  return static_cast<int>(std::lround(t.dwell_ratio() * t.hand_period_s() / spec_->dt()));
}

bool TossJuggler::BringInBalls() {
  while (BeatStep(next_add_beat_) - DwellSteps() <= step_) {
    const int beat = next_add_beat_++;
    if (schedule_.At(beat).change != BallChange::kAddBall) continue;
    const Hand hand = BeatHand(beat);
    if (world_.held_by(hand) >= 0) return false;
    int b = 0;
    while (b < static_cast<int>(balls_.size()) && !balls_[b].out) ++b;
    if (b == static_cast<int>(balls_.size())) balls_.push_back({});
    balls_[b] = {beat, false};
    world_.Hold(b, hand);
  }
  return true;
}

int TossJuggler::BeatStep(int beat) const {
  const config::TossConfig& t = spec_->toss();
  // Beat −1 is at t = 0: the run starts at a release, and the first throw from a resting hand
  // (beat 0) gets one beat of preparation, close to the throw task's D_ratio·P_hand ± jitter.
  const int beat_steps = static_cast<int>(std::lround(0.5 * t.hand_period_s() / spec_->dt()));
  return (beat + 1) * beat_steps;
}

void TossJuggler::PlaceInitialBalls(Rng* rng) {
  const double g = spec_->timing().gravity, dt = spec_->dt();
  const double jitter = options_.ball_noise;
  const config::TossConfig& t = spec_->toss();
  const int dwell_steps = static_cast<int>(std::lround(t.dwell_ratio() * t.hand_period_s() / dt));
  // The first beat still to come; throws on earlier beats were made at or before t = 0.
  int first_beat = 0;
  while (BeatStep(first_beat - 1) > 0) --first_beat;
  next_beat_ = first_beat;
  next_add_beat_ = first_beat;
  for (int j = first_beat - schedule_.first().max_throw(); j < first_beat; ++j) {
    const int v = Value(j);
    const int landing = j + v;
    if (v == 0 || landing < first_beat) continue;
    const int b = static_cast<int>(balls_.size());
    balls_.push_back({landing});
    if (BeatStep(landing) - dwell_steps <= 0) {  // already caught: in its hand
      world_.Hold(b, BeatHand(landing));
      continue;
    }
    // In flight on the schedule's parabola from the thrower's home point, τ after the release.
    const Hand thrower = BeatHand(j);
    const ThrowTiming timing = ComputeThrowTiming(v, thrower == Hand::kRight ? 0 : 1,
                                                  spec_->timing());
    const double tau = -BeatStep(j) * dt;
    const Vec2 p{spec_->home_x(thrower) + timing.v_x * tau + rng->Uniform(-jitter, jitter),
                 spec_->home_z() + timing.v_z * tau - 0.5 * g * tau * tau +
                     rng->Uniform(-jitter, jitter)};
    const double vj = options_.ball_speed_noise;
    world_.SetFree(b, p, {timing.v_x + rng->Uniform(-vj, vj),
                          timing.v_z - g * tau + rng->Uniform(-vj, vj)});
  }
}

Hand TossJuggler::DestinationHand(int ball) const { return BeatHand(balls_[ball].next_beat); }

bool TossJuggler::IsHandoff(int beat) const {
  const int v = Value(beat);
  return v == 1 || (v > 0 && ComputeThrowTiming(v, std::max(beat, 0), spec_->timing()).kind ==
                                 ThrowKind::kHandoff);
}

int TossJuggler::IncomingBall(Hand hand) const {
  int best = -1;
  for (int b = 0; b < static_cast<int>(balls_.size()); ++b) {
    if (world_.mode(b) != BallMode::kFree || DestinationHand(b) != hand) continue;
    if (best < 0 || balls_[b].next_beat < balls_[best].next_beat) best = b;
  }
  // A ball the other hand passes over (a 1) before `best` is due: the hand waits for it at home
  // instead of chasing `best` (it could not take both).
  const int passed = world_.held_by(Other(hand));
  if (best >= 0 && passed >= 0 && IsHandoff(balls_[passed].next_beat)) {
    const config::TossConfig& t = spec_->toss();
    const int dwell_steps =
        static_cast<int>(std::lround(t.dwell_ratio() * t.hand_period_s() / spec_->dt()));
    if (BeatStep(balls_[passed].next_beat) <= BeatStep(balls_[best].next_beat) - dwell_steps) {
      return -1;
    }
  }
  return best;
}

bool TossJuggler::HoldsThrow(Hand hand) const {
  const int held = world_.held_by(hand);
  if (held < 0) return false;
  const int beat = balls_[held].next_beat;
  return ComputeThrowTiming(Value(beat), beat, spec_->timing()).kind ==
         ThrowKind::kToss;
}

void TossJuggler::WriteObservation(Hand hand, float* obs) const {
  const int held = world_.held_by(hand);
  world_.WriteArmObservation(hand, held >= 0 ? held : IncomingBall(hand), obs);
  if (held >= 0) {
    const int beat = balls_[held].next_beat;
    const ThrowTiming timing = ComputeThrowTiming(Value(beat), beat, spec_->timing());
    obs[kTossCatchObs] = static_cast<float>((BeatStep(beat) - step_) * spec_->dt());
    obs[kTossCatchObs + 1] = static_cast<float>(TossSpec::MirrorSign(hand) * timing.v_x);
    obs[kTossCatchObs + 2] = static_cast<float>(timing.v_z);
  }
}

JointTargets TossJuggler::BaseTargets(Hand hand) const {
  const double wind = spec_->toss().base().estimate_wind() ? wind_.accel() : 0.0;
  const int held = world_.held_by(hand);
  if (held < 0) return base_->Catch(world_, hand, IncomingBall(hand), wind);
  if (!HoldsThrow(hand)) return base_->Home(world_, hand);  // a handoff or a hold
  const int beat = balls_[held].next_beat;
  return base_->Throw(world_, hand, std::max(1, BeatStep(beat) - step_),
                      base_->ReleaseVelocity(hand, Value(beat), wind));
}

void TossJuggler::Act(Hand hand) {
  const bool holding = world_.held_by(hand) >= 0;
  const EigenPolicy* policy = holding ? policies_.thrower : policies_.catcher;
  if (base_) {
    RowMatrix action;
    const float* residual = nullptr;
    if (policy != nullptr && (holding || IncomingBall(hand) >= 0)) {
      float obs[kTossThrowObs];
      WriteObservation(hand, obs);
      action = policy->MeanActions(obs, 1);
      residual = action.data();
    }
    world_.SetTargets(hand, base_->WithResidual(hand, BaseTargets(hand), residual));
    return;
  }
  if (policy == nullptr || (!holding && IncomingBall(hand) < 0)) {
    world_.SetHomeTargets(hand);
    return;
  }
  float obs[kTossThrowObs];
  WriteObservation(hand, obs);
  const RowMatrix action = policy->MeanActions(obs, 1);
  world_.SetAction(hand, action.data());
}

bool TossJuggler::DoBeat(int beat) {
  const int v = Value(beat);
  const Hand hand = BeatHand(beat);
  const int ball = world_.held_by(hand);
  if (v == 0 && schedule_.At(beat).change == BallChange::kRemoveBall) {
    if (ball < 0 || balls_[ball].next_beat != beat) return false;
    world_.Park(ball);  // put away
    balls_[ball].out = true;
    return true;
  }
  if (v == 0) return true;
  if (ball < 0 || balls_[ball].next_beat != beat) return false;
  if (IsHandoff(beat)) {
    if (world_.held_by(Other(hand)) >= 0) return false;
    world_.Hold(ball, Other(hand));
  } else {
    const ThrowTiming timing = ComputeThrowTiming(v, beat, spec_->timing());
    const Vec2 p = world_.palm_position(hand);
    result_.catch_starts.push_back(world_.ArmState(hand));
    Vec2 vel = world_.Release(ball);
    if (options_.ideal_release) {
      vel = {timing.v_x, timing.v_z};
      world_.SetFree(ball, p, vel);
    }
    position_error_sum_ += std::hypot(p.x - spec_->home_x(hand), p.z - spec_->home_z());
    const double velocity_error = std::hypot(vel.x - timing.v_x, vel.z - timing.v_z);
    velocity_error_sum_ += velocity_error;
    result_.max_velocity_error = std::max(result_.max_velocity_error, velocity_error);
    auto& [sum, count] = result_.velocity_error_by_value[v];
    sum += velocity_error;
    ++count;
    ++releases_;
    HandEvents& e = events_[static_cast<int>(hand)];
    e.released = true;
    e.value = v;
    e.release_position = p;
    e.release_velocity = vel;
    e.target_velocity = {timing.v_x, timing.v_z};
    e.good_throw = IsGoodThrow(*spec_, hand, v, p, vel);
    if (e.good_throw) ++result_.good_throws;
  }
  balls_[ball].next_beat = beat + v;
  ++result_.throws;
  return true;
}

TrajectoryBuilder TossJuggler::NewRecording(const TossSpec& spec, int balls,
                                            const std::string& config_path) {
  std::vector<std::string> outcomes = CommonOutcomeNames();
  for (const char* end : {"max_throws", "dropped", "missed_beat"}) outcomes.push_back(end);
  const std::vector<std::string> modes = {"catch", "throw"};
  std::vector<AnnotationChannel> channels = {
      {"beat", {}},          {"throws", {}},         {"right_mode", modes}, {"left_mode", modes},
      {"right_palm_x", {}},  {"right_palm_z", {}},   {"left_palm_x", {}},   {"left_palm_z", {}}};
  for (int b = 0; b < balls; ++b) {
    channels.push_back({absl::StrCat("ball", b, "_x"), {}});
    channels.push_back({absl::StrCat("ball", b, "_z"), {}});
    channels.push_back({absl::StrCat("ball", b, "_mode"), {"parked", "free", "held"}});
  }
  return TrajectoryBuilder("toss", config_path, spec.dt(), spec.model()->nq, std::move(outcomes),
                           std::move(channels));
}

void TossJuggler::Capture(TrajectoryBuilder* recording) const {
  if (recording == nullptr) return;
  std::vector<double> a = {static_cast<double>(next_beat_ - 1), static_cast<double>(result_.throws),
                           HoldsThrow(Hand::kRight) ? 1.0 : 0.0, HoldsThrow(Hand::kLeft) ? 1.0 : 0.0};
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const Vec2 palm = world_.palm_position(hand);
    a.push_back(palm.x);
    a.push_back(palm.z);
  }
  for (int b = 0; b < static_cast<int>(balls_.size()); ++b) {
    const Vec2 p = world_.ball_position(b);
    a.push_back(p.x);
    a.push_back(p.z);
    a.push_back(static_cast<double>(world_.mode(b)));
  }
  Outcome outcome = Outcome::kRunning;
  if (over_) {
    switch (result_.end) {
      case JuggleEnd::kMaxThrows: outcome = FamilyOutcome(0); break;
      case JuggleEnd::kDropped: outcome = FamilyOutcome(1); break;
      case JuggleEnd::kMissedBeat: outcome = FamilyOutcome(2); break;
      case JuggleEnd::kDiverged: outcome = Outcome::kDiverged; break;
    }
  }
  recording->Append(world_.time(), 0, world_.time(), outcome, a.data(), world_.data()->qpos);
}

void TossJuggler::Finish(JuggleEnd end, Hand hand) {
  over_ = true;
  end_hand_ = hand;
  result_.end = end;
  result_.seconds = world_.time();
  result_.releases = releases_;
  if (releases_ > 0) {
    result_.mean_velocity_error = velocity_error_sum_ / releases_;
    result_.mean_position_error = position_error_sum_ / releases_;
  }
  if (result_.catches > 0) result_.mean_catch_height_error = catch_height_error_sum_ / result_.catches;
}

bool TossJuggler::Step(const float* right_action, TrajectoryBuilder* recording) {
  events_ = {};
  if (!BringInBalls()) {
    Finish(JuggleEnd::kMissedBeat, BeatHand(next_add_beat_ - 1));
    Capture(recording);
    return false;
  }
  if (right_action != nullptr && base_) {
    world_.SetTargets(Hand::kRight,
                      base_->WithResidual(Hand::kRight, BaseTargets(Hand::kRight), right_action));
  } else if (right_action != nullptr) {
    world_.SetAction(Hand::kRight, right_action);
  } else {
    Act(Hand::kRight);
  }
  Act(Hand::kLeft);
  wind_.BeforeStep(world_);
  world_.Step();
  wind_.AfterStep(world_);
  ++step_;
  if (world_.diverged()) {
    Finish(JuggleEnd::kDiverged, Hand::kRight);
    return false;
  }
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const int ball = IncomingBall(hand);
    if (ball >= 0 && world_.CanCatch(ball, hand)) {
      result_.throw_starts.push_back(world_.ArmState(hand));
      HandEvents& e = events_[static_cast<int>(hand)];
      e.caught = true;
      e.catch_height_error = std::abs(spec_->home_z() - world_.ball_position(ball).z);
      catch_height_error_sum_ += e.catch_height_error;
      const Vec2 palm_v = world_.palm_velocity(hand);
      e.catch_palm_speed = std::hypot(palm_v.x, palm_v.z);
      world_.Hold(ball, hand);
      ++result_.catches;
    }
  }
  while (!over_ && BeatStep(next_beat_) <= step_) {
    if (!DoBeat(next_beat_)) {
      Finish(JuggleEnd::kMissedBeat, BeatHand(next_beat_));
    } else if (result_.throws >= options_.max_throws) {
      Finish(JuggleEnd::kMaxThrows, BeatHand(next_beat_));
    }
    ++next_beat_;
  }
  const double drop_z = spec_->toss().drop_z();
  for (int b = 0; !over_ && b < static_cast<int>(balls_.size()); ++b) {
    if (world_.mode(b) == BallMode::kFree && world_.ball_position(b).z < drop_z) {
      Finish(JuggleEnd::kDropped, DestinationHand(b));
    }
  }
  Capture(recording);
  return !over_;
}

std::unique_ptr<TossJuggler> TossJuggler::Clone() const {
  return std::unique_ptr<TossJuggler>(new TossJuggler(*this));  // the world copies exactly
}

JuggleRunResult TossJuggler::Run(TrajectoryBuilder* recording) {
  Capture(recording);
  while (Step(nullptr, recording)) {
  }
  return result_;
}

}  // namespace juggle::toss
