#include "envs/football/env.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/status_macros.h"
#include "envs/divergence.h"
#include "envs/football/kick_motion.h"
#include "envs/football/outcomes.h"
#include "envs/football/trap_kick.h"
#include "envs/humanoid/reference_dynamics.h"
#include "envs/humanoid/stance_balance.h"

namespace juggle::football {
namespace {

constexpr double kDegree = M_PI / 180;

double Norm3(const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// How a trap has failed so far (a lob on the turf first, another part first), or kRunning.
Outcome TrapFailure(const FootballSpec& spec, const TrapEpisode& e) {
  if (e.turf_before_touch && e.pass.kind == PassKind::kLob) return kGroundFirst;
  if (e.first_body >= 0 && e.first_body != spec.trap_bodies().body[e.part]) return kWrongPart;
  return Outcome::kRunning;
}

// Which part of the character a body is, for the kick's first touch (env.h): the spec's kicking
// foot, else by the humanoid's body names (configs/models/humanoid.xml; the left leg stands).
enum class TouchPart { kKickingFoot, kKickingLeg, kStandingLeg, kUpperBody };

TouchPart TouchPartOf(const FootballSpec& spec, int body) {
  if (body == spec.kick_foot_body()) return TouchPart::kKickingFoot;
  const char* name = mj_id2name(spec.model(), mjOBJ_BODY, body);
  const std::string n = name == nullptr ? "" : name;
  if (n == "right_knee" || n == "right_hip") return TouchPart::kKickingLeg;
  if (n == "left_ankle" || n == "left_knee" || n == "left_hip") return TouchPart::kStandingLeg;
  return TouchPart::kUpperBody;
}

}  // namespace

FootballEnv::FootballEnv(std::shared_ptr<const FootballSpec> spec, Rng rng)
    : spec_(std::move(spec)), model_(spec_->model()), data_(mj_makeData(model_)) {
  if (spec_->football().reference_feedforward() > 0) id_data_.reset(mj_makeData(model_));
  s_.rng = rng;
  s_.kick.after_touch.reserve(16);
}

std::unique_ptr<Env> FootballSpec::NewEnv(Rng rng) const {
  return std::make_unique<FootballEnv>(
      std::static_pointer_cast<const FootballSpec>(shared_from_this()), rng);
}

std::unique_ptr<EnvSnapshot> FootballEnv::Snapshot() const {
  auto snapshot = std::make_unique<FootballSnapshot>();
  snapshot->spec_fingerprint = spec_->fingerprint();
  snapshot->physics.Save(model_, data_.get());
  snapshot->state = s_;
  return snapshot;
}

absl::Status FootballEnv::Restore(const EnvSnapshot& snapshot) {
  RETURN_IF_ERROR(CheckSnapshotMatches(snapshot, spec_->family(), spec_->fingerprint()));
  const auto* football = dynamic_cast<const FootballSnapshot*>(&snapshot);
  if (football == nullptr) return absl::InvalidArgumentError("not a football env snapshot");
  football->physics.Restore(data_.get());
  s_ = football->state;
  return absl::OkStatus();
}

void FootballEnv::Reset(const AdaptiveWalk&) {
  s_.steps = 0;
  s_.touch_time_s = -1;
  s_.touch_body = -1;
  s_.touch_foot_speed = 0;
  s_.window_done = false;
  s_.score = {};
  s_.fell = false;
  s_.previous_action.fill(0.0f);
  s_.kick.touched = false;
  s_.kick.after_touch.clear();
  s_.kick_origin_s = 0;
  s_.touch_armed = true;
  if (!spec_->trap()) {
    ResetKick();
    return;
  }
  s_.trap = DrawTrapEpisode(*spec_, s_.rng);
  s_.kick_origin_s = -1;  // TRAP never kicks; TRAP_KICK kicks after the switch
  if (spec_->trap_kick()) DrawKickTarget();
  mj_resetData(model_, data_.get());
  s_.reference = spec_->standing_pose();
  mju_copy(data_->qpos, s_.reference.data(), humanoid::kCharacterNq);
  PlaceTrapBall(*spec_, s_.trap, data_.get());
  mj_forward(model_, data_.get());
}

void FootballEnv::DrawKickTarget() {
  const config::KickTargets& k = spec_->football().kick();
  Rng& rng = s_.rng;
  // Speed, azimuth off +x, elevation.
  const double speed = rng.Uniform(k.speed_min_mps(), k.speed_max_mps());
  const double azimuth = rng.Uniform(-k.azimuth_max_deg(), k.azimuth_max_deg()) * kDegree;
  const double elevation = rng.Uniform(k.elevation_min_deg(), k.elevation_max_deg()) * kDegree;
  s_.kick.target_speed = speed;
  s_.kick.target_direction[0] = std::cos(elevation) * std::cos(azimuth);
  s_.kick.target_direction[1] = std::cos(elevation) * std::sin(azimuth);
  s_.kick.target_direction[2] = std::sin(elevation);
}

void FootballEnv::ResetKick() {
  DrawKickTarget();
  const config::KickTargets& k = spec_->football().kick();
  Rng& rng = s_.rng;
  mj_resetData(model_, data_.get());
  s_.reference = spec_->standing_pose();
  mju_copy(data_->qpos, s_.reference.data(), humanoid::kCharacterNq);
  const PitchBall& b = spec_->ball();
  const double* foot = spec_->kick_foot_standing();
  double* ball = data_->qpos + b.qpos;
  const double jitter = k.position_jitter_m();
  ball[0] = foot[0] + k.ball_ahead_m() + rng.Uniform(-jitter, jitter);
  ball[1] = foot[1] + k.ball_side_m() + rng.Uniform(-jitter, jitter);
  ball[2] = b.radius;
  ball[3] = 1;
  ball[4] = ball[5] = ball[6] = 0;
  // Rolling without slipping: ω = ẑ × v / r.
  const double roll = rng.Uniform(0, k.ball_speed_max_mps());
  const double heading = rng.Uniform(-k.roll_heading_max_deg(), k.roll_heading_max_deg()) * kDegree;
  double* v = data_->qvel + b.dof;
  v[0] = roll * std::cos(heading);
  v[1] = roll * std::sin(heading);
  v[3] = -v[1] / b.radius;
  v[4] = v[0] / b.radius;
  mj_forward(model_, data_.get());
}

void FootballEnv::TargetVelocity(double v[3]) const {
  const double n = Norm3(s_.kick.target_direction);
  for (int c = 0; c < 3; ++c) v[c] = s_.kick.target_direction[c] / n * s_.kick.target_speed;
}

bool FootballEnv::Diverged() const { return SimulationDiverged(model_, data_.get()); }

bool FootballEnv::Fallen() const {
  const double dot = mju_dot(data_->qpos + 3, humanoid::kUprightRoot, 4);
  const double tilt_sin2 = std::max(0.0, 1.0 - dot * dot);
  return tilt_sin2 > spec_->football().max_tilt_sin2() ||
         data_->qpos[2] < spec_->football().min_root_height();
}

void FootballEnv::AddReferenceFeedforward(double t, double* feedforward) {
  const double half = 0.5 * spec_->control_dt();
  CharacterPose before, after;
  KickReferencePose(*spec_, t - half, {}, &before);
  KickReferencePose(*spec_, t + half, {}, &after);
  double tau[humanoid::kCharacterNv];
  humanoid::ReferenceInverseDynamics(spec_->joints(), model_, *data_, before, s_.reference, after,
                                     half, id_data_.get(), tau);
  const double gain = spec_->football().reference_feedforward();
  for (const humanoid::ActuatedJoint& joint : spec_->joints()) {
    const double limit = spec_->football().action_torque() * joint.torque_scale;
    for (int k = joint.dof_adr; k < joint.dof_adr + joint.dofs; ++k) {
      feedforward[k] += std::clamp(gain * tau[k], -limit, limit);
    }
  }
}

void FootballEnv::NoteTouches() {
  if (s_.touch_body >= 0) return;
  if (!s_.touch_armed) {
    s_.touch_armed = !BallTouchesCharacter(*spec_, data_.get());
    return;
  }
  const int ball_geom = spec_->ball().geom;
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    if (c.geom1 != ball_geom && c.geom2 != ball_geom) continue;
    const int other = c.geom1 == ball_geom ? c.geom2 : c.geom1;
    const int body = model_->geom_bodyid[other];
    if (body == 0) continue;  // the turf (world body)
    s_.touch_body = body;
    s_.touch_time_s = data_->time;
    s_.kick.touched = body == spec_->kick_foot_body();
    double velocity[6];  // rotational, then translational (world frame)
    mj_objectVelocity(model_, data_.get(), mjOBJ_GEOM, spec_->kick_foot_geom(), velocity, 0);
    s_.touch_foot_speed = Norm3(velocity + 3);
    return;
  }
}

StepResult FootballEnv::Step(const float* action, const AdaptiveWalk&) {
  const config::FootballConfig& f = spec_->football();
  // The trap's phase (TRAP, TRAP_KICK before the switch) or the kick's (on the kick's clock).
  const bool trap = !kicking();
  const double t = trap ? time_s() : kick_time_s();
  if (!trap) KickReferencePose(*spec_, t, {}, &s_.reference);
  double feedforward[humanoid::kCharacterNv] = {0};
  const double unit = f.action_torque();
  for (const humanoid::ActuatedJoint& joint : spec_->joints()) {
    for (int d = 0; d < joint.dofs; ++d) {
      feedforward[joint.dof_adr + d] =
          unit * joint.torque_scale *
          std::clamp(static_cast<double>(action[joint.dof_adr + d - 6]), -1.0, 1.0);
    }
  }
  if (id_data_ != nullptr && !trap) AddReferenceFeedforward(t, feedforward);
  const KickTimes kick = KickTimesOf(f.motion(), {});
  // One stance (the left foot) for TRAP's traps with the right leg and during the kick;
  // TRAP_KICK stands on both feet otherwise (it stands for seconds: the PD alone tips the
  // character over after about 1.4 s).
  const bool one_foot = trap ? f.task() == config::TRAP && (s_.trap.part == config::FOOT ||
                                                            s_.trap.part == config::LOWER_LEG)
                             : t >= kick.start && t < kick.end;
  if (f.has_stance_balance() && one_foot) {
    humanoid::AddStanceBalance(spec_->joints(), f.stance_balance(), humanoid::Foot::kLeft,
                               spec_->root_body(), unit, model_, data_.get(), feedforward);
  } else if (f.has_stance_balance() && spec_->trap_kick()) {
    humanoid::AddDoubleStanceBalance(spec_->joints(), f.stance_balance(), spec_->root_body(), unit,
                                     model_, data_.get(), feedforward);
  }
  for (int a = 0; a < kNumActions; ++a) s_.previous_action[a] = std::clamp(action[a], -1.0f, 1.0f);

  StepResult result;
  const bool touched_before = s_.touch_body >= 0;
  for (int k = 0; k < f.substeps(); ++k) {
    humanoid::StablePdTorques(spec_->joints(), s_.reference.data(), model_, data_.get(),
                              feedforward, data_->qfrc_applied);
    ClearDivergenceWarnings(data_.get());
    mj_step(model_, data_.get());
    if (Diverged()) {
      result.outcome = Outcome::kDiverged;
      break;
    }
    if (trap) {
      NoteTrapContacts(*spec_, data_.get(), &s_.trap);
    } else {
      NoteTouches();
    }
  }
  ++s_.steps;
  if (trap) {
    if (spec_->trap_kick()) {
      AfterTrapKickTrapStep(&result);
    } else {
      AfterTrapStep(&result);
    }
    return result;
  }
  AfterKickStep(touched_before, &result);
  return result;
}

void FootballEnv::AfterKickStep(bool touched_before, StepResult* out) {
  const config::FootballConfig& f = spec_->football();
  StepResult& result = *out;
  if (result.outcome == Outcome::kRunning && s_.touch_body >= 0) {
    if (!touched_before && !s_.kick.touched) result.outcome = kWrongTouch;
    const double since = data_->time - s_.touch_time_s;
    if (!s_.window_done && s_.kick.touched) {
      if (since <= kKickWindowS + 1e-9) {
        BallVelocitySample sample;
        sample.t = since;
        mju_copy3(sample.velocity, data_->qvel + spec_->ball().dof);
        s_.kick.after_touch.push_back(sample);
      }
      if (since + spec_->control_dt() > kKickWindowS + 1e-9) {
        s_.window_done = true;
        s_.score = ScoreKick(s_.kick, kKickWindowS);
      }
    }
    if (result.outcome == Outcome::kRunning && since >= f.settle_s() - 1e-9) {
      result.outcome = kKicked;
    }
  }
  if (result.outcome == Outcome::kRunning || result.outcome == kKicked) {
    if (Fallen()) {
      s_.fell = true;
      result.outcome = kFell;
    }
  }
  if (result.outcome == Outcome::kRunning && s_.steps >= f.max_episode_steps()) {
    result.outcome = Outcome::kTimeLimit;
  }
}

int FootballEnv::completions() const {
  if (spec_->trap_kick()) return kicking() && s_.window_done && s_.score.success && !s_.fell;
  if (spec_->trap()) {
    return s_.trap.settled && !s_.fell && ScoreTrap(s_.trap.attempt).success ? 1 : 0;
  }
  return s_.window_done && s_.score.success ? 1 : 0;
}

void FootballEnv::AfterTrapStep(StepResult* result) {
  const config::FootballConfig& f = spec_->football();
  TrapEpisode& e = s_.trap;
  if (result->outcome == Outcome::kRunning) {
    AfterTrapControlStep(*spec_, data_.get(), &e);
    if (const Outcome failed = TrapFailure(*spec_, e); failed != Outcome::kRunning) {
      result->outcome = failed;
    } else if (e.settled) {
      result->outcome = kTrapped;
    }
  }
  if (result->outcome == Outcome::kRunning || result->outcome == kTrapped) {
    if (Fallen()) {
      s_.fell = true;
      result->outcome = kFell;
    }
  }
  if (result->outcome == Outcome::kRunning && s_.steps >= f.max_episode_steps()) {
    result->outcome = Outcome::kTimeLimit;
  }
}

void FootballEnv::AfterTrapKickTrapStep(StepResult* result) {
  const config::FootballConfig& f = spec_->football();
  TrapEpisode& e = s_.trap;
  if (result->outcome == Outcome::kRunning) {
    AfterTrapControlStep(*spec_, data_.get(), &e);
    if (const Outcome failed = TrapFailure(*spec_, e); failed != Outcome::kRunning) {
      result->outcome = failed;
    } else if (Fallen()) {  // before the switch: a fall while trapping is the trap's
      s_.fell = true;
      result->outcome = kFell;
    } else if (e.first_body >= 0 && BallKickable(*spec_, data_.get())) {
      s_.kick_origin_s = time_s();  // the kick's clock starts; its touches count from here
      s_.touch_armed = !BallTouchesCharacter(*spec_, data_.get());
      if (!e.settled) EndTrap(*spec_, data_.get(), &e);  // the ball is controlled: in the zone
    } else if (e.first_body >= 0 &&
               data_->time - e.first_touch_s >= f.trap_kick().wait_s() - 1e-9) {
      result->outcome = kOutOfReach;
    }
  }
  if (result->outcome == Outcome::kRunning && s_.steps >= f.max_episode_steps()) {
    result->outcome = Outcome::kTimeLimit;
  }
}

void FootballEnv::AppendTrapMetrics(std::vector<NamedValue>* out) const {
  const TrapEpisode& e = s_.trap;
  const TrapScore score = ScoreTrap(e.attempt, kRelativeSpeedFrames);
  // TRAP_KICK: a fall after the switch is the kick's, not the trap's.
  const bool fell_trapping = s_.fell && !(spec_->trap_kick() && kicking());
  const bool success = e.settled && !fell_trapping && score.success;
  out->push_back({"trap_success", success ? 1.0 : 0.0});
  out->push_back({"trap_touch_before_ground",
                  e.first_body >= 0 && (e.pass.kind == PassKind::kGround || !e.turf_before_touch)
                      ? 1.0
                      : 0.0});
  if (success) out->push_back({"trap_handball", score.handball ? 1.0 : 0.0});
  out->push_back({"trap_arms_touched", e.arms_touched ? 1.0 : 0.0});
  if (score.measured_speed) out->push_back({"trap_rbspt_mps", score.relative_speed});
  out->push_back({"trap_part", static_cast<double>(e.part)});
  out->push_back({"trap_lob", e.pass.kind == PassKind::kLob ? 1.0 : 0.0});
  const double* v = e.pass.velocity;
  const double g = -model_->opt.gravity[2];
  const double vz = e.pass.kind == PassKind::kLob ? v[2] - g * e.pass.meet_s : 0;
  out->push_back({"trap_meet_speed_mps", e.pass.kind == PassKind::kLob
                                             ? std::sqrt(v[0] * v[0] + v[1] * v[1] + vz * vz)
                                             : e.pass.arrival_speed});
  if (e.settled) out->push_back({"trap_end_distance_m", e.end_distance_m});
}

void FootballEnv::WriteObservation(float* obs) const {
  const double* qpos = data_->qpos;
  const double* qvel = data_->qvel;
  const humanoid::Joints& joints = spec_->joints();
  int i = 0;
  obs[i++] = qpos[2];
  obs[i++] = (qpos[3] - M_SQRT1_2) * 4;
  obs[i++] = (qpos[4] - M_SQRT1_2) * 4;
  obs[i++] = qpos[5] * 4;
  obs[i++] = qpos[6] * 4;
  for (int adr : {joints[humanoid::kChest].qpos_adr, joints[humanoid::kNeck].qpos_adr}) {
    obs[i++] = qpos[adr];
    for (int c = 1; c < 4; ++c) obs[i++] = qpos[adr + c] * 2;
  }
  for (int q = joints[humanoid::kRightShoulder].qpos_adr; q < humanoid::kCharacterNq; ++q) {
    obs[i++] = qpos[q];
  }
  for (int c = 0; c < 3; ++c) obs[i++] = qvel[c];
  double world[3];
  mju_rotVecQuat(world, qvel + 3, qpos + 3);  // root angular velocity: local -> world
  for (int c = 0; c < 3; ++c) obs[i++] = world[c];
  for (int v = 6; v < humanoid::kCharacterNv; ++v) obs[i++] = qvel[v] / 10;
  const double* ball = qpos + spec_->ball().qpos;
  const double* ball_vel = qvel + spec_->ball().dof;
  for (int c = 0; c < 3; ++c) obs[i++] = ball[c] - qpos[c];
  for (int c = 0; c < 3; ++c) obs[i++] = ball_vel[c] / 10;
  for (int c = 0; c < 3; ++c) obs[i++] = ball_vel[3 + c] / 100;
  if (!kicking()) {
    // The designated part (its TrapPart number / 4), the pass's kind, the time to the meeting.
    obs[i++] = static_cast<float>(s_.trap.part) / 4;
    obs[i++] = s_.trap.pass.kind == PassKind::kLob ? 1 : 0;
    obs[i++] = 0;
    obs[i++] = s_.trap.pass.meet_s - time_s();
    obs[i++] = s_.trap.first_body >= 0 ? 1 : 0;
  } else {
    double target[3];
    TargetVelocity(target);
    for (int c = 0; c < 3; ++c) obs[i++] = target[c] / 10;
    obs[i++] = spec_->football().motion().start_s() - kick_time_s();
    obs[i++] = s_.touch_body >= 0 ? 1 : 0;
  }
  for (int k = 0; k < i; ++k) {
    if (!std::isfinite(obs[k])) obs[k] = 0;  // never hand a non-finite number to a policy
  }
}

void FootballEnv::AppendEpisodeMetrics(std::vector<NamedValue>* out) const {
  if (spec_->trap()) AppendTrapMetrics(out);
  if (spec_->trap_kick()) {
    out->push_back({"trap_kick_switched", kicking() ? 1.0 : 0.0});
    if (kicking()) {
      out->push_back({"trap_kick_switch_s", s_.kick_origin_s});
    } else {
      AppendUnkickedBall(out);
    }
    out->push_back({"trap_kick_success", static_cast<double>(completions())});
  }
  if (kicking()) AppendKickMetrics(out);
  out->push_back({"fell", s_.fell ? 1.0 : 0.0});
}

void FootballEnv::AppendUnkickedBall(std::vector<NamedValue>* out) const {
  const PitchBall& b = spec_->ball();
  const double* p = data_->qpos + b.qpos;
  const double* v = data_->qvel + b.dof;
  const double* foot = spec_->kick_foot_standing();
  out->push_back({"trap_kick_ball_ahead_m", p[0] - foot[0]});
  out->push_back({"trap_kick_ball_across_m", p[1] - foot[1]});
  out->push_back({"trap_kick_ball_height_m", p[2] - b.radius});
  out->push_back({"trap_kick_ball_speed_mps", std::hypot(v[0], v[1])});
  out->push_back({"trap_kick_zone_distance_m", KickZoneDistance(*spec_, p[0], p[1])});
}

void FootballEnv::AppendKickMetrics(std::vector<NamedValue>* out) const {
  const bool success = s_.window_done && s_.score.success;
  out->push_back({"kick_success", success ? 1.0 : 0.0});
  if (success) {
    out->push_back({"kick_direction_deviation_deg", s_.score.direction_deviation_deg});
    out->push_back({"kick_speed_deviation_mps", s_.score.speed_deviation_mps});
    const KickFloor floor = KickDeviationFloor(s_.kick, kKickWindowS);
    out->push_back({"kick_direction_floor_deg", floor.direction_deg});
    out->push_back({"kick_speed_floor_mps", floor.speed_mps});
    const KickErrors errors = SignedKickErrors(s_.kick, kKickWindowS);
    out->push_back({"kick_azimuth_error_deg", errors.azimuth_deg});
    out->push_back({"kick_elevation_error_deg", errors.elevation_deg});
    out->push_back({"kick_speed_error_mps", errors.speed_mps});
    double speed = 0;
    for (const BallVelocitySample& sample : s_.kick.after_touch) speed += Norm3(sample.velocity);
    out->push_back({"kick_speed_mps", speed / std::max<size_t>(1, s_.kick.after_touch.size())});
  }
  out->push_back({"kick_target_speed_mps", s_.kick.target_speed});
  if (s_.kick.touched) {
    out->push_back({"kick_foot_speed_mps", s_.touch_foot_speed});
    out->push_back({"kick_touch_s", s_.touch_time_s});
  }
  if (s_.touch_body >= 0) {
    const TouchPart part = TouchPartOf(*spec_, s_.touch_body);
    out->push_back({"kick_touch_kicking_leg", part == TouchPart::kKickingLeg ? 1.0 : 0.0});
    out->push_back({"kick_touch_standing_leg", part == TouchPart::kStandingLeg ? 1.0 : 0.0});
    out->push_back({"kick_touch_upper_body", part == TouchPart::kUpperBody ? 1.0 : 0.0});
  }
}

}  // namespace juggle::football
