#include "envs/soccer_juggle/env.h"

#include <algorithm>
#include <cmath>

#include "common/status_macros.h"
#include "envs/ballistic.h"
#include "envs/soccer_juggle/reference_pose.h"

namespace juggle::soccer_juggle {

namespace {

// MuJoCo warnings that mean the simulation can no longer be trusted.
constexpr int kWatchedWarnings[] = {mjWARN_BADQACC, mjWARN_BADQPOS, mjWARN_BADQVEL,
                                    mjWARN_CONTACTFULL, mjWARN_CNSTRFULL};

// sin²(θ/2) of the rotation between unit quaternions a and b.
double RotationSin2(const double* a, const double* b) {
  const double dot = mju_dot(a, b, 4);
  return std::max(0.0, 1.0 - dot * dot);
}

}  // namespace

JuggleEnv::JuggleEnv(std::shared_ptr<const JuggleSpec> spec, Rng rng)
    : spec_(std::move(spec)), model_(spec_->model()), data_(mj_makeData(model_)) {
  s_.rng = rng;
  s_.events.reserve(8);
  if (spec_->env().reference_feedforward() != 0) id_data_.reset(mj_makeData(model_));
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
  PlaceAtReference();
}

bool JuggleEnv::ResetAt(int node, const AdaptiveWalk& walk) {
  s_.events.clear();
  spec_->cursor().ResetAt(node, walk, &s_.rng, &s_.cursor);
  PlaceAtReference();
  return true;
}

void JuggleEnv::PlaceAtReference() {
  s_.steps = 0;
  s_.kick_touched = s_.kick_rewarded = false;
  mj_resetData(model_, data_.get());
  const config::StartVariation& start = spec_->env().start();
  // A random phase of the initial DOWN node: the fall is already under way.
  double fall_s = 0;
  if (start.random_phase_fraction() > 0 &&
      spec_->graph().node(s_.cursor.current).stage == config::DOWN &&
      s_.rng.Uniform() < start.random_phase_fraction()) {
    s_.cursor.phase = s_.rng.Uniform(0, start.max_phase());
    fall_s = s_.cursor.phase / s_.cursor.phase_speed * spec_->control_dt();
  }
  s_.swing_adjust = {};
  ComputeReferencePose(*spec_, s_.cursor.current, s_.cursor.phase, &s_.reference, s_.swing_adjust);
  mju_copy(data_->qpos, s_.reference.data(), kCharacterNq);
  const BallReference ball = spec_->cursor().DesiredBall(s_.cursor, s_.cursor.phase);
  double* ball_qpos = data_->qpos + spec_->ball_qpos();
  ball_qpos[0] = s_.reference[0] + ball.x;
  ball_qpos[1] = s_.reference[1] + ball.y;
  ball_qpos[2] = ball.z;
  ball_qpos[3] = 1;
  ball_qpos[4] = ball_qpos[5] = ball_qpos[6] = 0;
  mju_zero(data_->qvel, model_->nv);
  data_->qvel[spec_->ball_dof() + 2] = -spec_->env().gravity() * fall_s;
  PerturbStart(start);
  mj_forward(model_, data_.get());
}

void JuggleEnv::PerturbStart(const config::StartVariation& start) {
  double* qpos = data_->qpos;
  double* qvel = data_->qvel;
  auto noise = [this](double amplitude) {
    return amplitude > 0 ? s_.rng.Uniform(-amplitude, amplitude) : 0.0;
  };
  double* ball = qpos + spec_->ball_qpos();
  double* ball_vel = qvel + spec_->ball_dof();
  for (int c = 0; c < 3; ++c) ball[c] += noise(start.ball_position());
  for (int c = 0; c < 3; ++c) ball_vel[c] += noise(start.ball_velocity());
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_->joint(j);
    if (joint.dofs == 3) {
      double rotation[3];
      for (double& r : rotation) r = noise(start.joint_angle());
      mju_quatIntegrate(qpos + joint.qpos_adr, rotation, 1.0);
    } else {
      qpos[joint.qpos_adr] += noise(start.joint_angle());
    }
    for (int d = 0; d < joint.dofs; ++d) qvel[joint.dof_adr + d] += noise(start.joint_speed());
  }
}

void JuggleEnv::ApplyTorques(const double* feedforward) {
  const double h = model_->opt.timestep;
  const double* qpos = data_->qpos;
  const double* qvel = data_->qvel;
  double* tau = data_->qfrc_applied;
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_->joint(j);
    const int dof = joint.dof_adr;
    if (joint.dofs == 3) {
      // Stable PD: kp·(err − h·q̇); the damping kd·q̇ is the joint's implicit damping.
      double err[3];
      mju_subQuat(err, s_.reference.data() + joint.qpos_adr, qpos + joint.qpos_adr);
      for (int d = 0; d < 3; ++d) {
        tau[dof + d] = joint.kp * (err[d] - h * qvel[dof + d]) + feedforward[dof + d];
      }
    } else {
      const double err = s_.reference[joint.qpos_adr] - qpos[joint.qpos_adr];
      tau[dof] = joint.kp * (err - h * qvel[dof]) + feedforward[dof];
    }
  }
  const config::Vec3& force = spec_->env().ball_force();
  double* xfrc = data_->xfrc_applied + 6 * spec_->ball_body();
  xfrc[0] = force.x();
  xfrc[1] = force.y();
  xfrc[2] = force.z();
}

void JuggleEnv::AddReferenceFeedforward(double phase, double* feedforward) {
  // Reference pose, velocity and acceleration by central differences over ± half a control
  // step; the character is lifted out of contact and its root held still (qacc 0).
  constexpr double kLift = 100;  // m
  const int nq = model_->nq, nv = model_->nv;
  const double dt = 0.5 * spec_->control_dt();
  const double dphase = 0.5 * s_.cursor.phase_speed;
  mjData* d = id_data_.get();
  mjMARKSTACK;
  mjtNum* q_minus = mj_stackAlloc(d, nq);
  mjtNum* q_plus = mj_stackAlloc(d, nq);
  mjtNum* v_minus = mj_stackAlloc(d, nv);
  mjtNum* v_plus = mj_stackAlloc(d, nv);
  CharacterPose pose;
  auto load = [&](const CharacterPose& p, mjtNum* qpos) {
    mju_copy(qpos, data_->qpos, nq);  // the ball stays where it is, far below the character
    mju_copy(qpos, p.data(), kCharacterNq);
    qpos[2] += kLift;
  };
  load(s_.reference, d->qpos);
  ComputeReferencePose(*spec_, s_.cursor.current, phase - dphase, &pose, s_.swing_adjust);
  load(pose, q_minus);
  ComputeReferencePose(*spec_, s_.cursor.current, phase + dphase, &pose, s_.swing_adjust);
  load(pose, q_plus);
  mj_differentiatePos(model_, v_minus, dt, q_minus, d->qpos);
  mj_differentiatePos(model_, v_plus, dt, d->qpos, q_plus);
  for (int i = 0; i < nv; ++i) {
    d->qvel[i] = 0.5 * (v_minus[i] + v_plus[i]);
    d->qacc[i] = (v_plus[i] - v_minus[i]) / dt;
  }
  mju_zero(d->qvel, 6);
  mju_zero(d->qacc, 6);
  mju_zero(d->qvel + spec_->ball_dof(), 6);
  mju_zero(d->qacc + spec_->ball_dof(), 6);
  mj_inverse(model_, d);
  const double gain = spec_->env().reference_feedforward();
  const double h = model_->opt.timestep;
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_->joint(j);
    for (int k = joint.dof_adr; k < joint.dof_adr + joint.dofs; ++k) {
      // qfrc_inverse includes the damping drag kd·q̇; kp·h·q̇ is the stable PD's own drag.
      feedforward[k] += gain * (d->qfrc_inverse[k] + joint.kp * h * d->qvel[k]);
    }
  }
  mjFREESTACK;
}

void JuggleEnv::AddStanceBalance(double* feedforward) {
  const config::StanceBalance& b = spec_->env().stance_balance();
  const config::ReferencePose& ref = spec_->graph().node(s_.cursor.current).spec.pose();
  if (!ref.has_leg_swing()) return;
  const bool kick_left = ref.leg_swing().side() == config::LEFT;
  const ActuatedJoint& hip = spec_->joint(kick_left ? kRightHip : kLeftHip);
  const ActuatedJoint& ankle = spec_->joint(kick_left ? kRightAnkle : kLeftAnkle);
  const int foot = model_->dof_bodyid[ankle.dof_adr];
  // Each term is clamped to the joint's feed-forward range, as a policy action would be.
  auto add = [&](const ActuatedJoint& joint, const double tau[3]) {
    const double limit = spec_->env().action_torque() * joint.torque_scale;
    for (int i = 0; i < 3; ++i) {
      feedforward[joint.dof_adr + i] += std::clamp(tau[i], -limit, limit);
    }
  };
  double tau_ankle[3] = {0, 0, 0}, tau_hip[3] = {0, 0, 0};
  if (b.com_kp() != 0 || b.com_kd() != 0) {
    mj_subtreeVel(model_, data_.get());  // COM velocity of the character (the root's subtree)
    const int root = spec_->root_body();
    const double* com = data_->subtree_com + 3 * root;
    const double* vel = data_->subtree_linvel + 3 * root;
    const double* pos = data_->xpos + 3 * foot;
    const double ex = com[0] - pos[0] - b.com_x(), ey = com[1] - pos[1] - b.com_y();
    const double world[3] = {-(b.com_kp() * ey + b.com_kd() * vel[1]),
                             b.com_kp() * ex + b.com_kd() * vel[0], 0};
    mju_mulMatTVec(tau_ankle, data_->xmat + 9 * foot, world, 3, 3);  // into the foot frame
  }
  if (b.pelvis_kp() != 0 || b.pelvis_kd() != 0 || b.yaw_kp() != 0 || b.yaw_kd() != 0) {
    double tilt[3];
    mju_subQuat(tilt, data_->qpos + 3, kUprightQuat);
    const double* w = data_->qvel + 3;
    for (int i : {0, 2}) tau_hip[i] = b.pelvis_kp() * tilt[i] + b.pelvis_kd() * w[i];
    tau_hip[1] = b.yaw_kp() * tilt[1] + b.yaw_kd() * w[1];  // about the root's vertical (y)
  }
  add(ankle, tau_ankle);
  add(hip, tau_hip);
}

bool JuggleEnv::Diverged() const {
  for (int w : kWatchedWarnings) {
    if (data_->warning[w].number > 0) return true;
  }
  for (int i = 0; i < model_->nq; ++i) {
    if (!std::isfinite(data_->qpos[i])) return true;
  }
  for (int i = 0; i < model_->nv; ++i) {
    if (!std::isfinite(data_->qvel[i])) return true;
  }
  return false;
}

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
    if (!rt.contact_allowed[body]) return kBadContact;
    s_.touched_this_step = true;
    if (!stall && std::abs(spec_->cursor().SecondsFromContact(s_.cursor, substep_phase)) >
                      node.contact_window_s() + 1e-9) {
      return kContactTiming;
    }
    if (ball_z < spec_->env().termination().min_ball_height()) return kBallLost;
  }
  return Outcome::kRunning;
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
  if (rt.atw_foot_body >= 0 && !rt.atw_angle.empty() && s_.cursor.phase_speed > 0) {
    const bool up = spec_->graph().node(s_.cursor.current).stage == config::UP;
    const double local = (s_.cursor.phase - (up ? 0.5 : 0.0)) / 0.5;  // [0, 1] over the node
    const double skip = rt.atw_skip_steps * s_.cursor.phase_speed / 0.5;
    if (local > skip && local < 1.0 - skip) {
      const int bins = static_cast<int>(rt.atw_angle.size());
      const int bin = std::clamp(static_cast<int>(local * bins), 0, bins - 1);
      const double* foot = data_->xpos + 3 * rt.atw_foot_body;
      const double psi = std::atan2(foot[2] - ball[2], foot[1] - ball[1]);
      const double desired = rt.atw_angle[bin];
      const double dc = std::cos(psi) - std::cos(desired);
      const double ds = std::sin(psi) - std::sin(desired);
      if (dc * dc + ds * ds > rt.atw_max_chord2) return kAroundTheWorld;
    }
  }
  if (rt.stall_body >= 0) {
    const double* body = data_->xpos + 3 * rt.stall_body;
    double diff[3];
    mju_sub3(diff, ball, body);
    if (mju_norm3(diff) > rt.stall_max_distance) return kStallLost;
  }
  return Outcome::kRunning;
}

float JuggleEnv::ComputeReward(const BallReference& ball_ref) const {
  const config::RewardConfig& w = spec_->env().reward();
  const double* qpos = data_->qpos;
  const double* qvel = data_->qvel;
  double joint_err = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_->joint(j);
    const int adr = joint.qpos_adr;
    if (joint.dofs == 3) {
      joint_err += RotationSin2(qpos + adr, s_.reference.data() + adr);
    } else {
      const double d = qpos[adr] - s_.reference[adr];
      joint_err += d * d;
    }
  }
  const double dz = qpos[2] - s_.reference[2];
  const double pos_err = qvel[0] * qvel[0] + qvel[1] * qvel[1] + dz * dz;
  const double ori_err = RotationSin2(qpos + 3, s_.reference.data() + 3);
  const double* ball = qpos + spec_->ball_qpos();
  const double bx = ball_ref.x - (ball[0] - qpos[0]);
  const double by = ball_ref.y - (ball[1] - qpos[1]);
  const double bz = ball_ref.z - ball[2];
  const double ball_err = bx * bx + by * by + w.ball_z_weight() * bz * bz;
  const double r = w.w_position() * std::exp(-pos_err) +
                   w.w_orientation() * std::exp(-w.orientation_k() * ori_err) +
                   w.w_joint() * std::exp(-w.joint_k() * joint_err) +
                   w.w_ball() * std::exp(-ball_err);
  return static_cast<float>(w.scale() * r);
}

void JuggleEnv::UpdateSwingAdjust() {
  if (!spec_->env().has_kick_feedback()) return;
  const GraphNode& node = spec_->graph().node(s_.cursor.current);
  if (node.stage != config::DOWN || s_.kick_touched || !node.spec.pose().has_leg_swing()) return;
  const double* qpos = data_->qpos;
  const double* ball = qpos + spec_->ball_qpos();
  const double* ball_vel = data_->qvel + spec_->ball_dof();
  if (ball[2] - node.spec.contact_height() <= 0) return;  // at the contact height already: hold
  const BallisticCrossing c =
      DescendingCrossing(ball, ball_vel, spec_->env().gravity(), node.spec.contact_height());
  const double ex = c.x - qpos[0] - node.spec.ball_target().x();
  const double ey = c.y - qpos[1] - node.spec.ball_target().y();
  const double late = c.t + spec_->cursor().SecondsFromContact(s_.cursor, s_.cursor.phase);
  const config::KickFeedback& f = spec_->env().kick_feedback();
  const bool left = node.spec.pose().leg_swing().side() == config::LEFT;
  s_.swing_adjust.hip = f.hip_per_m() * ex;
  s_.swing_adjust.knee = f.knee_per_m() * ex;
  s_.swing_adjust.abduction = f.abduction_per_m() * ey * (left ? 1 : -1);
  const double cycle_s = spec_->control_dt() / s_.cursor.phase_speed;
  s_.swing_adjust.phase = -f.timing() * late / cycle_s;
}

float JuggleEnv::KickReward() {
  if (s_.touched_this_step) {
    s_.kick_touched = true;
    return 0;
  }
  const config::RewardConfig& w = spec_->env().reward();
  const double* ball = data_->qpos + spec_->ball_qpos();
  const double* ball_vel = data_->qvel + spec_->ball_dof();
  if (!s_.kick_touched || s_.kick_rewarded || ball_vel[2] <= 0 || w.w_kick() == 0) return 0;
  s_.kick_rewarded = true;
  // The DOWN node the ball is sent to: the next one after the current node.
  const CursorState& c = s_.cursor;
  int target = c.next;
  if (spec_->graph().node(c.current).stage == config::DOWN) target = c.next_next;
  if (spec_->graph().node(target).stage != config::DOWN) return 0;  // stalls: no ballistic target
  const config::NodeSpec& node = spec_->graph().node(target).spec;
  const double g = spec_->env().gravity();
  const double apex = ApexHeight(ball[2], ball_vel[2], g);
  // A ball kicked from below the contact height is judged where it comes back down through
  // its own height.
  const double t_land =
      SecondsToFall(ball_vel[2], std::max(0.0, ball[2] - node.contact_height()), g);
  const double* root = data_->qpos;
  const double dx = ball[0] + ball_vel[0] * t_land - root[0] - node.ball_target().x();
  const double dy = ball[1] + ball_vel[1] * t_land - root[1] - node.ball_target().y();
  const double de = apex - NominalApexHeight(node, g);
  return static_cast<float>(
      w.w_kick() * std::exp(-w.kick_apex_k() * de * de - w.kick_landing_k() * (dx * dx + dy * dy)));
}

StepResult JuggleEnv::Step(const float* action, const AdaptiveWalk& walk) {
  s_.events.clear();
  s_.touched_this_step = false;
  const double phase0 = s_.cursor.phase;
  UpdateSwingAdjust();
  ComputeReferencePose(*spec_, s_.cursor.current, phase0, &s_.reference, s_.swing_adjust);
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
  if (id_data_ != nullptr) AddReferenceFeedforward(phase0, feedforward);
  if (spec_->env().has_stance_balance()) AddStanceBalance(feedforward);

  StepResult result;
  const int substeps = spec_->env().substeps();
  for (int k = 0; k < substeps && result.outcome == Outcome::kRunning; ++k) {
    ApplyTorques(feedforward);
    for (int w : kWatchedWarnings) data_->warning[w].number = 0;
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
  result.reward = result.outcome == Outcome::kDiverged ? 0.0f : ComputeReward(ball_ref);
  if (result.outcome == Outcome::kRunning) result.reward += KickReward();
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
