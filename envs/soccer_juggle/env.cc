#include "envs/soccer_juggle/env.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/divergence.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/soccer_juggle/start_state.h"

namespace juggle::soccer_juggle {

JuggleEnv::JuggleEnv(std::shared_ptr<const JuggleSpec> spec, Rng rng)
    : spec_(std::move(spec)), model_(spec_->model()), data_(mj_makeData(model_)), base_(*spec_) {
  s_.rng = rng;
  s_.events.reserve(8);
}

std::unique_ptr<Env> JuggleSpec::NewEnv(Rng rng) const {
  return std::make_unique<JuggleEnv>(
      std::static_pointer_cast<const JuggleSpec>(shared_from_this()), rng);
}

std::unique_ptr<EnvSnapshot> JuggleEnv::Snapshot() const {
  auto snapshot = std::make_unique<JuggleSnapshot>();
  snapshot->spec_fingerprint = spec_->fingerprint();
  snapshot->physics.Save(model_, data_.get());
  snapshot->state = s_;
  return snapshot;
}

absl::Status JuggleEnv::Restore(const EnvSnapshot& snapshot) {
  RETURN_IF_ERROR(CheckSnapshotMatches(snapshot, spec_->family(), spec_->fingerprint()));
  const auto* juggle = dynamic_cast<const JuggleSnapshot*>(&snapshot);
  if (juggle == nullptr) return absl::InvalidArgumentError("not a soccer_juggle env snapshot");
  juggle->physics.Restore(data_.get());
  s_ = juggle->state;
  return absl::OkStatus();
}

void JuggleEnv::Reset(const AdaptiveWalk& walk) {
  s_.events.clear();
  spec_->cursor().Reset(walk, &s_.rng, &s_.cursor);
  StartEpisode();
}

void JuggleEnv::Resteer(const AdaptiveWalk& walk) { spec_->cursor().Resteer(walk, &s_.cursor); }

bool JuggleEnv::ResetAt(int node, const AdaptiveWalk& walk) {
  s_.events.clear();
  spec_->cursor().ResetAt(node, walk, &s_.rng, &s_.cursor);
  StartEpisode();
  return true;
}

void JuggleEnv::StartEpisode() {
  s_.steps = 0;
  s_.kick_touched = s_.kick_rewarded = s_.touched_this_step = false;
  s_.touched_body = -1;
  s_.bad_contact_geom = -1;
  s_.swing_adjust = {};
  s_.reward = {};
  s_.previous_action.fill(0.0f);
  PlaceAtStart(*spec_, &s_.rng, &s_.cursor, &s_.reference, data_.get());
}

void JuggleEnv::ApplyTorques(const double* feedforward) {
  humanoid::StablePdTorques(spec_->joints(), s_.reference.data(), model_, data_.get(),
                            feedforward, data_->qfrc_applied);
  const config::Vec3& force = spec_->env().ball_force();
  double* xfrc = data_->xfrc_applied + 6 * spec_->ball_body();
  xfrc[0] = force.x();
  xfrc[1] = force.y();
  xfrc[2] = force.z();
}

bool JuggleEnv::Diverged() const { return SimulationDiverged(model_, data_.get()); }

Outcome JuggleEnv::CheckBallContacts(double substep_phase) {
  const int ball_geom = spec_->ball_geom();
  const NodeRuntime& rt = spec_->node_runtime(s_.cursor.current);
  const config::NodeSpec& node = spec_->graph().node(s_.cursor.current).spec;
  const bool stall = node.stage() == config::STALL;
  const double ball_z = data_->qpos[spec_->ball_qpos() + 2];
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    if (c.geom1 != ball_geom && c.geom2 != ball_geom) continue;
    const int other = c.geom1 == ball_geom ? c.geom2 : c.geom1;
    const int body = model_->geom_bodyid[other];
    if (!rt.contact_allowed[body]) {
      s_.bad_contact_geom = other;
      return kBadContact;
    }
    s_.touched_this_step = true;
    if (s_.touched_body < 0) s_.touched_body = body;
    if (!stall && std::abs(spec_->cursor().SecondsFromContact(s_.cursor, substep_phase)) >
                      node.contact_window_s() + 1e-9) {
      return kContactTiming;
    }
    if (ball_z < spec_->env().termination().min_ball_height()) return kBallLost;
  }
  return Outcome::kRunning;
}

std::string JuggleEnv::EndingDetail() const {
  const int geom = s_.bad_contact_geom;
  if (geom < 0) return {};
  const int body = model_->geom_bodyid[geom];
  if (body == 0) {
    const char* name = mj_id2name(model_, mjOBJ_GEOM, geom);
    return name != nullptr ? name : "world";
  }
  const char* name = mj_id2name(model_, mjOBJ_BODY, body);
  return name != nullptr ? name : absl::StrCat("body ", body);
}

Outcome JuggleEnv::CheckTermination(const BallReference& ball_ref) const {
  const config::TerminationConfig& term = spec_->env().termination();
  const double* qpos = data_->qpos;
  if (RotationSin2(qpos + 3, kUprightQuat) > term.max_tilt_sin2()) return kFell;
  if (qpos[2] < term.min_root_height()) return kFell;
  const double* ball = qpos + spec_->ball_qpos();
  if (std::abs(ball[0] - qpos[0] - ball_ref.x) > term.max_ball_dx() ||
      std::abs(ball[1] - qpos[1] - ball_ref.y) > term.max_ball_dy() ||
      ball[2] < term.min_ball_height()) {
    return kBallLost;
  }
  const NodeRuntime& rt = spec_->node_runtime(s_.cursor.current);
  if (AroundTheWorldChord2() > rt.atw_max_chord2) return kAroundTheWorld;
  if (rt.stall_body >= 0) {
    const double* body = data_->xpos + 3 * rt.stall_body;
    double diff[3];
    mju_sub3(diff, ball, body);
    if (mju_norm3(diff) > rt.stall_max_distance) return kStallLost;
  }
  return Outcome::kRunning;
}

double JuggleEnv::AroundTheWorldChord2() const {
  const NodeRuntime& rt = spec_->node_runtime(s_.cursor.current);
  if (rt.atw_foot_body < 0 || rt.atw_angle.empty() || s_.cursor.phase_speed <= 0) return -1;
  const bool up = spec_->graph().node(s_.cursor.current).stage == config::UP;
  const double local = (s_.cursor.phase - (up ? 0.5 : 0.0)) / 0.5;  // [0, 1] over the node
  const double skip = rt.atw_skip_steps * s_.cursor.phase_speed / 0.5;
  if (local <= skip || local >= 1.0 - skip) return -1;
  const int bins = static_cast<int>(rt.atw_angle.size());
  const int bin = std::clamp(static_cast<int>(local * bins), 0, bins - 1);
  const double* ball = data_->qpos + spec_->ball_qpos();
  const double* foot = data_->xpos + 3 * rt.atw_foot_body;
  const double psi = std::atan2(foot[2] - ball[2], foot[1] - ball[1]);
  const double desired = rt.atw_angle[bin];
  const double dc = std::cos(psi) - std::cos(desired);
  const double ds = std::sin(psi) - std::sin(desired);
  return dc * dc + ds * ds;
}

double JuggleEnv::AroundTheWorldViolation() const {
  const double chord2 = AroundTheWorldChord2();
  if (chord2 < 0) return 0;
  return chord2 / spec_->node_runtime(s_.cursor.current).atw_max_chord2;
}

float JuggleEnv::TrackKick() {
  if (s_.touched_this_step) {
    s_.kick_touched = true;
    return 0;
  }
  const double ball_vz = data_->qvel[spec_->ball_dof() + 2];
  if (!s_.kick_touched || s_.kick_rewarded || ball_vz <= 0 || spec_->env().reward().w_kick() == 0) {
    return 0;
  }
  s_.kick_rewarded = true;
  return KickReward(*spec_, *data_, s_.cursor);
}

StepResult JuggleEnv::Step(const float* action, const AdaptiveWalk& walk) {
  s_.events.clear();
  s_.touched_this_step = false;
  s_.touched_body = -1;
  const double phase0 = s_.cursor.phase;
  base_.UpdateSwingAdjust(*data_, s_.cursor, s_.kick_touched, &s_.swing_adjust);
  ComputeCursorPose(*spec_, s_.cursor, phase0, &s_.reference, s_.swing_adjust);
  const BallReference ball_ref = spec_->cursor().DesiredBall(s_.cursor, phase0);

  double feedforward[kCharacterNv] = {0};
  const double unit = spec_->env().action_torque();
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_->joint(j);
    for (int d = 0; d < joint.dofs; ++d) {
      feedforward[joint.dof_adr + d] =
          unit * joint.torque_scale *
          std::clamp(static_cast<double>(action[joint.dof_adr + d - 6]), -1.0, 1.0);
    }
  }
  base_.AddFeedforward(s_.cursor, s_.reference, s_.swing_adjust, data_.get(), feedforward);
  for (int a = 0; a < kNumActions; ++a) s_.previous_action[a] = std::clamp(action[a], -1.0f, 1.0f);

  StepResult result;
  const int substeps = spec_->env().substeps();
  for (int k = 0; k < substeps && result.outcome == Outcome::kRunning; ++k) {
    ApplyTorques(feedforward);
    ClearDivergenceWarnings(data_.get());
    mj_step(model_, data_.get());
    if (Diverged()) {
      result.outcome = Outcome::kDiverged;
      break;
    }
    result.outcome = CheckBallContacts(phase0 + s_.cursor.phase_speed * (k + 1) / substeps);
  }

  if (result.outcome == Outcome::kRunning) {
    const int before = s_.cursor.current;
    spec_->cursor().Advance(walk, &s_.rng, &s_.cursor, &s_.events);
    if (s_.cursor.current != before &&
        spec_->graph().node(s_.cursor.current).stage == config::DOWN) {
      s_.kick_touched = s_.kick_rewarded = false;  // a new cycle
    }
    result.outcome = CheckTermination(ball_ref);
  }
  s_.reward = {};
  if (result.outcome != Outcome::kDiverged) {
    s_.reward = TrackingReward(*spec_, *data_, s_.reference, ball_ref);
  }
  if (result.outcome == Outcome::kRunning) s_.reward.kick = TrackKick();
  result.reward = s_.reward.Total();
  ++s_.steps;
  if (result.outcome == Outcome::kRunning && s_.steps >= spec_->env().max_episode_steps()) {
    result.outcome = Outcome::kTimeLimit;
  }
  if (result.terminated()) spec_->cursor().Fail(s_.cursor, &s_.events);
  return result;
}

void JuggleEnv::WriteObservation(float* obs) const {
  const double* qpos = data_->qpos;
  const double* qvel = data_->qvel;
  int i = 0;
  obs[i++] = qpos[2];
  obs[i++] = (qpos[3] - M_SQRT1_2) * 4;
  obs[i++] = (qpos[4] - M_SQRT1_2) * 4;
  obs[i++] = qpos[5] * 4;
  obs[i++] = qpos[6] * 4;
  for (int adr : {spec_->joint(kChest).qpos_adr, spec_->joint(kNeck).qpos_adr}) {
    obs[i++] = qpos[adr];
    for (int c = 1; c < 4; ++c) obs[i++] = qpos[adr + c] * 2;
  }
  for (int q = spec_->joint(kRightShoulder).qpos_adr; q < kCharacterNq; ++q) obs[i++] = qpos[q];
  for (int c = 0; c < 3; ++c) obs[i++] = qvel[c];
  double world[3];
  mju_rotVecQuat(world, qvel + 3, qpos + 3);  // root angular velocity: local -> world
  for (int c = 0; c < 3; ++c) obs[i++] = world[c];
  for (int v = 6; v < kCharacterNv; ++v) obs[i++] = qvel[v] / 10;
  obs[i++] = s_.cursor.apex_height;  // the release's always-zero "speed" slot carries H here
  const double* ball = qpos + spec_->ball_qpos();
  const double* ball_vel = qvel + spec_->ball_dof();
  for (int c = 0; c < 3; ++c) obs[i++] = ball[c] - qpos[c];
  for (int c = 0; c < 3; ++c) obs[i++] = ball_vel[c] / 10;
  mju_rotVecQuat(world, ball_vel + 3, ball + 3);
  for (int c = 0; c < 3; ++c) obs[i++] = world[c] / 10;
  obs[i++] = s_.cursor.phase_speed * 15;  // = release's phase units (150 per cycle) / 10
  obs[i++] = std::cos(2 * M_PI * s_.cursor.phase);
  obs[i++] = std::sin(2 * M_PI * s_.cursor.phase);
  const int n = spec_->graph().num_nodes();
  std::fill(obs + i, obs + i + 3 * n, 0.0f);
  obs[i + s_.cursor.current] = 1;
  obs[i + n + s_.cursor.next] = 1;
  obs[i + 2 * n + s_.cursor.next_next] = 1;
  if (spec_->env().ball_error_observation()) {
    i += 3 * n;
    const BallReference ref = spec_->cursor().DesiredBall(s_.cursor, s_.cursor.phase);
    const BallReference ref_vel = spec_->cursor().DesiredBallVelocity(s_.cursor, s_.cursor.phase);
    obs[i++] = ball[0] - qpos[0] - ref.x;
    obs[i++] = ball[1] - qpos[1] - ref.y;
    obs[i++] = ball[2] - ref.z;
    obs[i++] = (ball_vel[0] - ref_vel.x) / 10;
    obs[i++] = (ball_vel[1] - ref_vel.y) / 10;
    obs[i++] = (ball_vel[2] - ref_vel.z) / 10;
    for (int k = i - kBallErrorObs; k < i; ++k) {
      if (!std::isfinite(obs[k])) obs[k] = 0;
    }
  }
  if (spec_->env().previous_action_observation()) {
    if (!spec_->env().ball_error_observation()) i += 3 * n;
    for (int a = 0; a < kNumActions; ++a) {
      obs[i++] = std::isfinite(s_.previous_action[a]) ? s_.previous_action[a] : 0.0f;
    }
  }
  // Never hand a non-finite number to a policy.
  for (int k = 0; k < kObsBase; ++k) {
    if (!std::isfinite(obs[k])) obs[k] = 0;
  }
}

void JuggleEnv::AppendAnnotations(std::vector<double>* out) const {
  out->push_back(s_.cursor.current);
  out->push_back(s_.cursor.phase);
}

}  // namespace juggle::soccer_juggle
