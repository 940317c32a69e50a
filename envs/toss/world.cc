#include "envs/toss/world.h"

#include <algorithm>
#include <cmath>

#include "envs/ballistic.h"

namespace juggle::toss {
namespace {

constexpr int kHands[2] = {0, 1};
Hand HandOf(int h) { return static_cast<Hand>(h); }

// Parked balls sit here, far to the side and out of every observation's way.
constexpr double kParkX = 5.0, kParkZ = 0.0;

}  // namespace

TossWorld::TossWorld(std::shared_ptr<const TossSpec> spec)
    : spec_(std::move(spec)), model_(spec_->model()), data_(mj_makeData(model_)) {
  Reset(nullptr, 0, 0);
}

TossWorld::TossWorld(const TossWorld& other) : TossWorld(other.spec_) {
  Snapshot s;
  other.Save(&s);
  Restore(s);
}

void TossWorld::Reset(Rng* rng, double angle_noise_rad, double speed_noise_rad_s) {
  mj_resetData(model_, data_.get());
  diverged_ = false;
  // One draw, applied to both arms as mirror images: a world is symmetric at reset.
  std::array<double, kTossJoints> angle_noise{}, speed_noise{};
  if (rng != nullptr) {
    for (int j = 0; j < kTossJoints; ++j) {
      angle_noise[j] = rng->Uniform(-angle_noise_rad, angle_noise_rad);
      speed_noise[j] = rng->Uniform(-speed_noise_rad_s, speed_noise_rad_s);
    }
    angle_noise[0] = speed_noise[0] = 0;  // the shared neck starts centred
  }
  for (int h : kHands) {
    const TossArmJoints& arm = spec_->arm(HandOf(h));
    const double mirror = TossSpec::MirrorSign(HandOf(h));
    for (int j = 0; j < kTossJoints; ++j) {
      data_->qpos[arm.qpos[j]] = mirror * (spec_->home()[j] + angle_noise[j]);
      data_->qvel[arm.dof[j]] = mirror * speed_noise[j];
    }
    SetHomeTargets(HandOf(h));
  }
  for (int b = 0; b < kTossBalls; ++b) Park(b);
  mj_forward(model_, data_.get());
  for (int h : kHands) {
    for (int j = 0; j < kTossJoints; ++j) {
      prev_speed_[h][j] = data_->qvel[spec_->arm(HandOf(h)).dof[j]];
    }
    prev_palm_[h] = palm_position(HandOf(h));
  }
}

TossArmState TossWorld::ArmState(Hand hand) const {
  const TossArmJoints& arm = spec_->arm(hand);
  const double mirror = TossSpec::MirrorSign(hand);
  TossArmState state;
  for (int j = 0; j < kTossJoints; ++j) {
    state.angle[j] = mirror * data_->qpos[arm.qpos[j]];
    state.speed[j] = mirror * data_->qvel[arm.dof[j]];
  }
  return state;
}

void TossWorld::SetArmState(Hand hand, const TossArmState& state) {
  const TossArmJoints& arm = spec_->arm(hand);
  const double mirror = TossSpec::MirrorSign(hand);
  for (int j = 0; j < kTossJoints; ++j) {
    data_->qpos[arm.qpos[j]] = mirror * state.angle[j];
    data_->qvel[arm.dof[j]] = mirror * state.speed[j];
    prev_speed_[static_cast<int>(hand)][j] = data_->qvel[arm.dof[j]];
  }
  mj_forward(model_, data_.get());
  prev_palm_[static_cast<int>(hand)] = palm_position(hand);
}

void TossWorld::PlaceBall(int ball, Vec2 p, Vec2 v) {
  const TossBallJoints& j = spec_->ball(ball);
  data_->qpos[j.qpos_x] = p.x - j.origin_x;
  data_->qpos[j.qpos_z] = p.z - j.origin_z;
  data_->qvel[j.dof_x] = v.x;
  data_->qvel[j.dof_z] = v.z;
  prev_ball_[ball] = p;
}

void TossWorld::SetFree(int ball, Vec2 position, Vec2 velocity) {
  balls_[ball].mode = BallMode::kFree;
  PlaceBall(ball, position, velocity);
}

void TossWorld::Hold(int ball, Hand hand) {
  balls_[ball] = {BallMode::kHeld, hand};
  PlaceBall(ball, palm_position(hand), palm_velocity(hand));
}

Vec2 TossWorld::Release(int ball) {
  const Vec2 v = palm_velocity(balls_[ball].holder);
  SetFree(ball, palm_position(balls_[ball].holder), v);
  return v;
}

void TossWorld::Park(int ball) {
  balls_[ball].mode = BallMode::kParked;
  PlaceBall(ball, {kParkX + ball, kParkZ}, {0, 0});
}

int TossWorld::held_by(Hand hand) const {
  for (int b = 0; b < kTossBalls; ++b) {
    if (balls_[b].mode == BallMode::kHeld && balls_[b].holder == hand) return b;
  }
  return -1;
}

void TossWorld::SetAction(Hand hand, const float* action) {
  const double mirror = TossSpec::MirrorSign(hand);
  const double scale = spec_->toss().action_scale();
  for (int j = 0; j < kTossJoints; ++j) {
    const double a = std::clamp(static_cast<double>(action[j]), -1.0, 1.0);
    target_[static_cast<int>(hand)][j] = mirror * (spec_->home()[j] + scale * a);
  }
}

void TossWorld::SetHomeTargets(Hand hand) {
  const double mirror = TossSpec::MirrorSign(hand);
  for (int j = 0; j < kTossJoints; ++j) {
    target_[static_cast<int>(hand)][j] = mirror * spec_->home()[j];
  }
}

void TossWorld::SetTargets(Hand hand, const std::array<double, kTossJoints>& targets) {
  target_[static_cast<int>(hand)] = targets;
}

double TossWorld::wind() const {
  return wind_override_.has_value() ? *wind_override_ : spec_->toss().wind_force();
}

void TossWorld::Step() {
  const double kp = spec_->toss().kp(), h = spec_->dt();
  mju_zero(data_->qfrc_applied, model_->nv);
  for (int hand : kHands) {
    const TossArmJoints& arm = spec_->arm(HandOf(hand));
    for (int j = 0; j < kTossJoints; ++j) {
      prev_speed_[hand][j] = data_->qvel[arm.dof[j]];
      if (j == 0 && hand == 1) continue;  // the shared neck is driven once
      const double target = j == 0 ? 0.5 * (target_[0][0] + target_[1][0]) : target_[hand][j];
      data_->qfrc_applied[arm.dof[j]] =
          kp * (target - data_->qpos[arm.qpos[j]] - h * data_->qvel[arm.dof[j]]);
    }
  }
  const double wind = this->wind();
  for (int b = 0; b < kTossBalls; ++b) {
    const TossBallJoints& j = spec_->ball(b);
    if (balls_[b].mode == BallMode::kFree) {
      data_->qfrc_applied[j.dof_x] = wind;
    } else if (balls_[b].mode == BallMode::kHeld) {
      // The held ball's weight pulls on the palm.
      const int site = spec_->arm(balls_[b].holder).palm_site;
      const double mass = model_->body_mass[model_->dof_bodyid[j.dof_x]];
      mjtNum force[3] = {0, 0, -mass * spec_->timing().gravity}, torque[3] = {0, 0, 0};
      mj_applyFT(model_, data_.get(), force, torque, data_->site_xpos + 3 * site,
                 model_->site_bodyid[site], data_->qfrc_applied);
    }
  }
  for (int hand : kHands) prev_palm_[hand] = palm_position(HandOf(hand));
  for (int b = 0; b < kTossBalls; ++b) prev_ball_[b] = ball_position(b);
  mj_step(model_, data_.get());
  mj_forward(model_, data_.get());
  FollowPalms();
  bool finite = true;
  for (int i = 0; i < model_->nq && finite; ++i) finite = std::isfinite(data_->qpos[i]);
  for (int i = 0; i < model_->nv && finite; ++i) finite = std::isfinite(data_->qvel[i]);
  if (!finite || data_->warning[mjWARN_BADQACC].number > 0) diverged_ = true;
}

void TossWorld::FollowPalms() {
  for (int b = 0; b < kTossBalls; ++b) {
    if (balls_[b].mode == BallMode::kHeld) {
      PlaceBall(b, palm_position(balls_[b].holder), palm_velocity(balls_[b].holder));
    } else if (balls_[b].mode == BallMode::kParked) {
      Park(b);
    }
  }
}

bool TossWorld::CanCatch(int ball, Hand hand) const {
  if (balls_[ball].mode != BallMode::kFree || held_by(hand) >= 0) return false;
  if (ball_velocity(ball).z >= 0) return false;
  // The ball relative to the palm moves from `from` to `to` over the step; the closest point of
  // that segment to the palm.
  const Vec2 p = palm_position(hand), b = ball_position(ball);
  const Vec2 pp = prev_palm_[static_cast<int>(hand)], bp = prev_ball_[ball];
  const Vec2 from{bp.x - pp.x, bp.z - pp.z}, to{b.x - p.x, b.z - p.z};
  const Vec2 d{to.x - from.x, to.z - from.z};
  const double len2 = d.x * d.x + d.z * d.z;
  const double s = len2 > 0 ? std::clamp(-(from.x * d.x + from.z * d.z) / len2, 0.0, 1.0) : 1.0;
  return std::hypot(from.x + s * d.x, from.z + s * d.z) < spec_->toss().catch_radius();
}

double TossWorld::Effort(Hand hand) const {
  const TossArmJoints& arm = spec_->arm(hand);
  double sum = 0;
  for (int j = 0; j < kTossJoints; ++j) {
    sum += std::abs(data_->qvel[arm.dof[j]] - prev_speed_[static_cast<int>(hand)][j]);
  }
  return sum;
}

void TossWorld::WriteArmObservation(Hand hand, int ball, float* obs) const {
  const double mirror = TossSpec::MirrorSign(hand);
  const double hx = spec_->toss().hand_x(), hz = spec_->home_z();
  const Vec2 p = palm_position(hand), v = palm_velocity(hand);
  const Vec2 bp = ball >= 0 ? ball_position(ball) : p;
  const Vec2 bv = ball >= 0 ? ball_velocity(ball) : Vec2{0, 0};
  const double values[kTossCatchObs - kTossJoints] = {
      mirror * p.x - hx, p.z - hz, mirror * v.x, v.z,
      mirror * bp.x - hx, bp.z - hz, mirror * bv.x, bv.z};
  for (int i = 0; i < kTossCatchObs - kTossJoints; ++i) obs[i] = static_cast<float>(values[i]);
  const TossArmJoints& arm = spec_->arm(hand);
  for (int j = 0; j < kTossJoints; ++j) {
    obs[kTossCatchObs - kTossJoints + j] = static_cast<float>(mirror * data_->qpos[arm.qpos[j]]);
  }
}

Vec2 TossWorld::palm_position(Hand hand) const {
  const mjtNum* p = data_->site_xpos + 3 * spec_->arm(hand).palm_site;
  return {p[0], p[2]};
}

Vec2 TossWorld::palm_velocity(Hand hand) const {
  mjtNum v[6];
  mj_objectVelocity(model_, data_.get(), mjOBJ_SITE, spec_->arm(hand).palm_site, v, 0);
  return {v[3], v[5]};
}

Vec2 TossWorld::ball_position(int ball) const {
  const TossBallJoints& j = spec_->ball(ball);
  return {j.origin_x + data_->qpos[j.qpos_x], j.origin_z + data_->qpos[j.qpos_z]};
}

Vec2 TossWorld::ball_velocity(int ball) const {
  const TossBallJoints& j = spec_->ball(ball);
  return {data_->qvel[j.dof_x], data_->qvel[j.dof_z]};
}

BallisticLanding PredictLanding(Vec2 position, Vec2 velocity, double z, double g) {
  const double t = SecondsToFall(velocity.z, position.z - z, g);
  if (!(t >= 0)) return {};  // never comes down through z (NaN: never reaches it)
  return {position.x + velocity.x * t, t};
}

bool IsGoodThrow(const TossSpec& spec, Hand thrower, int value, Vec2 position, Vec2 velocity) {
  const Hand catcher =
      value % 2 == 1 ? (thrower == Hand::kRight ? Hand::kLeft : Hand::kRight) : thrower;
  const BallisticLanding landing =
      PredictLanding(position, velocity, spec.home_z(), spec.timing().gravity);
  return landing.time > 0 &&
         std::abs(landing.x - spec.home_x(catcher)) < spec.toss().catch_radius() &&
         std::abs(landing.time - FlightTimeEq1(value, spec.timing())) < 0.1;
}

void TossWorld::Save(Snapshot* out) const {
  out->physics.Save(model_, data_.get());
  out->balls = balls_;
  out->target = target_;
  out->prev_speed = prev_speed_;
  out->prev_ball = prev_ball_;
  out->prev_palm = prev_palm_;
  out->diverged = diverged_;
}

void TossWorld::Restore(const Snapshot& s) {
  s.physics.Restore(data_.get());
  balls_ = s.balls;
  target_ = s.target;
  prev_speed_ = s.prev_speed;
  prev_ball_ = s.prev_ball;
  prev_palm_ = s.prev_palm;
  diverged_ = s.diverged;
}

}  // namespace juggle::toss
