#include "planner/soccer_cost.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "envs/ballistic.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/reference_pose.h"

namespace juggle::planner {

using soccer_juggle::CursorState;
using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

namespace {

double Square(double x) { return x * x; }

// The residuals of a ball crossing `node`'s contact height `seconds_to_contact` from now.
KickOutcome OutcomeAt(const JuggleEnv& env, int node, double seconds_to_contact,
                      const LandingAnchors* anchors) {
  const JuggleSpec& spec = env.spec();
  const config::NodeSpec& target = spec.graph().node(node).spec;
  const mjData* d = env.data();
  const double* ball = d->qpos + spec.ball_qpos();
  const double* vel = d->qvel + spec.ball_dof();
  const double g = spec.env().gravity();
  const BallisticCrossing c = DescendingCrossing(ball, vel, g, target.contact_height());
  KickOutcome out;
  out.valid = true;
  out.timing = c.t - seconds_to_contact;
  double root[2] = {d->qpos[0], d->qpos[1]};
  if (anchors != nullptr && anchors->stance && anchors->stance_body[node] >= 0) {
    const double* foot = d->xpos + 3 * anchors->stance_body[node];
    root[0] = foot[0] + anchors->root_from_stance[node][0];
    root[1] = foot[1] + anchors->root_from_stance[node][1];
  }
  out.dx = c.x - root[0] - target.ball_target().x();
  out.dy = c.y - root[1] - target.ball_target().y();
  out.apex = ApexHeight(ball[2], vel[2], g) - NominalApexHeight(target, g);
  return out;
}

}  // namespace

bool MissedThisCycle(const JuggleEnv& env) {
  return !env.state().kick_touched &&
         env.spec().graph().node(env.node()).stage == config::UP;
}

LandingAnchors MakeLandingAnchors(const JuggleSpec& spec, bool stance) {
  LandingAnchors a;
  a.stance = stance;
  const int nodes = spec.graph().num_nodes();
  a.root_from_stance.assign(nodes, {0, 0});
  a.stance_body.assign(nodes, -1);
  const mjModel* m = spec.model();
  MjDataPtr scratch(mj_makeData(m));
  for (int n = 0; n < nodes; ++n) {
    const config::ReferencePose& pose = spec.graph().node(n).spec.pose();
    if (!pose.has_leg_swing()) continue;
    const bool kick_left = pose.leg_swing().side() == config::LEFT;
    const int ankle = spec.joint(kick_left ? soccer_juggle::kRightAnkle
                                           : soccer_juggle::kLeftAnkle).dof_adr;
    a.stance_body[n] = m->dof_bodyid[ankle];
    soccer_juggle::CharacterPose ref;
    soccer_juggle::ComputeReferencePose(spec, n, 0.5, &ref);
    mju_copy(scratch->qpos, ref.data(), soccer_juggle::kCharacterNq);
    mj_kinematics(m, scratch.get());
    a.root_from_stance[n] = {ref[0] - scratch->xpos[3 * a.stance_body[n]],
                             ref[1] - scratch->xpos[3 * a.stance_body[n] + 1]};
  }
  return a;
}

KickOutcome PredictKickOutcome(const JuggleEnv& env, const LandingAnchors* anchors) {
  const JuggleSpec& spec = env.spec();
  const CursorState& c = env.cursor();
  // The DOWN node the ball is sent to: the next one after the current cycle's contact.
  const bool down = spec.graph().node(c.current).stage == config::DOWN;
  const int target = down ? c.next_next : c.next;
  if (target < 0 || spec.graph().node(target).stage != config::DOWN || c.phase_speed <= 0) {
    return {};
  }
  // The clock's next contact: φ runs to 1 (this cycle) and on to 0.5 of the next.
  const double seconds = (1.5 - c.phase) / c.phase_speed * spec.control_dt();
  return OutcomeAt(env, target, seconds, anchors);
}

KickOutcome PredictApproach(const JuggleEnv& env, const LandingAnchors* anchors) {
  const JuggleSpec& spec = env.spec();
  const CursorState& c = env.cursor();
  if (spec.graph().node(c.current).stage != config::DOWN || c.phase_speed <= 0) return {};
  return OutcomeAt(env, c.current, -spec.cursor().SecondsFromContact(c, c.phase), anchors);
}

double BallClearance(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const mjModel* m = spec.model();
  const mjData* d = env.data();
  const std::vector<char>& allowed = spec.node_runtime(env.node()).contact_allowed;
  const double* ball = d->qpos + spec.ball_qpos();
  const double ball_radius = m->geom_rbound[spec.ball_geom()];
  double best = 1e9;
  for (int g = 0; g < m->ngeom; ++g) {
    if (!allowed[m->geom_bodyid[g]]) continue;
    double diff[3];
    mju_sub3(diff, ball, d->geom_xpos + 3 * g);
    best = std::min(best, mju_norm3(diff) - m->geom_rbound[g] - ball_radius);
  }
  return std::max(best, 0.0);
}

void ImpactTracker::Begin(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const mjModel* m = spec.model();
  const mjData* d = env.data();
  bodies_.clear();
  for (int b = 1; b < m->nbody; ++b) {
    for (int n = 0; n < spec.graph().num_nodes(); ++n) {
      if (spec.node_runtime(n).contact_allowed[b]) {
        bodies_.push_back(b);
        break;
      }
    }
  }
  jacobian_.resize(3 * m->nv);
  was_touched_ = env.state().kick_touched;
  // One step back, at the state's acceleration (the env's last forward pass), so that a touch in
  // the rollout's first step is measured too, the same way for every candidate.
  std::vector<double> earlier(d->qvel, d->qvel + m->nv);
  mju_addToScl(earlier.data(), d->qacc, -spec.control_dt(), m->nv);
  BodyVelocities(env, earlier.data(), &velocity_[1]);
  BodyVelocities(env, d->qvel, &velocity_[0]);
  mju_copy3(ball_velocity_, d->qvel + spec.ball_dof());
}

void ImpactTracker::BodyVelocities(const JuggleEnv& env, const double* qvel,
                                   std::vector<double>* out) {
  const mjModel* m = env.spec().model();
  out->resize(3 * bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) {
    // The joint velocities are the step's end, the Jacobian of its last substep's start
    // (mj_step's kinematics): one substep of motion apart.
    mj_jacBodyCom(m, env.data(), jacobian_.data(), nullptr, bodies_[i]);
    mju_mulMatVec(out->data() + 3 * i, jacobian_.data(), qvel, 3, m->nv);
  }
}

double ImpactTracker::AfterStep(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const mjModel* m = spec.model();
  const mjData* d = env.data();
  const bool first_touch = env.state().kick_touched && !was_touched_;
  was_touched_ = env.state().kick_touched;
  double acceleration = std::numeric_limits<double>::quiet_NaN();
  const auto tracked = std::find(bodies_.begin(), bodies_.end(), env.state().touched_body);
  if (first_touch && tracked != bodies_.end()) {
    // The impulse's direction: the ball's velocity change less what gravity and the env's
    // constant force on the ball (env.ball_force) gave it.
    const double dt = spec.control_dt();
    const config::Vec3& force = spec.env().ball_force();
    const double per_mass = dt / m->body_mass[spec.ball_body()];
    double n[3];
    mju_sub3(n, d->qvel + spec.ball_dof(), ball_velocity_);
    n[0] -= force.x() * per_mass;
    n[1] -= force.y() * per_mass;
    n[2] -= force.z() * per_mass - spec.env().gravity() * dt;
    if (mju_normalize3(n) < 0.05) {  // a graze: straight up
      n[0] = n[1] = 0;
      n[2] = 1;
    }
    const size_t i = tracked - bodies_.begin();
    double change[3];
    mju_sub3(change, velocity_[0].data() + 3 * i, velocity_[1].data() + 3 * i);
    acceleration = mju_dot3(change, n) / dt;
  }
  velocity_[1].swap(velocity_[0]);
  BodyVelocities(env, d->qvel, &velocity_[0]);
  mju_copy3(ball_velocity_, d->qvel + spec.ball_dof());
  return acceleration;
}

double BodyCost(const JuggleEnv& env, const config::PlannerCost& w) {
  const JuggleSpec& spec = env.spec();
  const mjData* d = env.data();
  const double* q = d->qpos;
  // The root's up axis is its local y, forward its local x (y-up joint frames).
  double up[3], forward[3];
  const double y_axis[3] = {0, 1, 0}, x_axis[3] = {1, 0, 0};
  mju_rotVecQuat(up, y_axis, q + 3);
  mju_rotVecQuat(forward, x_axis, q + 3);
  const double tilt = std::acos(std::clamp(up[2], -1.0, 1.0));
  const double yaw = std::atan2(forward[1], forward[0]);
  // Capture point of the COM (root velocity as the COM's) against the stance foot, or the
  // feet's middle when no leg swings.
  const double* com = d->subtree_com + 3 * spec.root_body();
  const double* v = d->qvel;
  const double g = spec.env().gravity();
  const double lead = std::sqrt(std::max(com[2], 0.1) / g);
  const config::ReferencePose& pose = spec.graph().node(env.node()).spec.pose();
  const int right = spec.model()->dof_bodyid[spec.joint(soccer_juggle::kRightAnkle).dof_adr];
  const int left = spec.model()->dof_bodyid[spec.joint(soccer_juggle::kLeftAnkle).dof_adr];
  double foot[2];
  if (pose.has_leg_swing()) {
    const int stance = pose.leg_swing().side() == config::LEFT ? right : left;
    foot[0] = d->xpos[3 * stance];
    foot[1] = d->xpos[3 * stance + 1];
  } else {
    foot[0] = 0.5 * (d->xpos[3 * right] + d->xpos[3 * left]);
    foot[1] = 0.5 * (d->xpos[3 * right + 1] + d->xpos[3 * left + 1]);
  }
  const double cp = std::hypot(com[0] + lead * v[0] - foot[0], com[1] + lead * v[1] - foot[1]);
  const double height = q[2] - env.reference_pose()[2];
  const double speed = std::hypot(v[0], v[1]);
  return w.tilt() * Square(tilt / w.tilt_scale()) + w.yaw() * Square(yaw / w.yaw_scale()) +
         w.capture_point() * Square(cp / w.capture_point_scale()) +
         w.root_height() * Square(height / w.root_height_scale()) +
         w.com_speed() * Square(speed / w.com_speed_scale());
}

SoccerRolloutScorer::SoccerRolloutScorer(const config::PlannerCost& cost, int horizon,
                                         const LandingAnchors* anchors)
    : cost_(cost), horizon_(std::max(horizon, 1)), anchors_(anchors) {}

void SoccerRolloutScorer::Begin(const JuggleEnv& env) {
  // A kick whose ball is already on its way was scored by an earlier plan; one whose ball is
  // still on the body is this plan's to score.
  scored_this_cycle_ = env.state().kick_touched && !env.state().touched_this_step;
  impact_.Begin(env);
}

void SoccerRolloutScorer::AfterStep(const JuggleEnv& env, const float* action,
                                    const StepResult& r) {
  ++steps_;
  double a2 = 0, change2 = 0;
  for (int i = 0; i < kNumActions; ++i) {
    a2 += Square(action[i]);
    if (has_previous_) change2 += Square(action[i] - previous_action_[i]);
    previous_action_[i] = action[i];
  }
  has_previous_ = true;
  effort_ += (cost_.action() * a2 + cost_.action_change() * change2) / kNumActions;
  const soccer_juggle::JuggleEnvState& s = env.state();
  const double impact = impact_.AfterStep(env);
  if (std::isfinite(impact)) {
    cycle_impact_ = impact;
    const double outside = std::max({impact - cost_.impact_acceleration_max(),
                                     cost_.impact_acceleration_min() - impact, 0.0});
    impact_cost_ +=
        cost_.impact_acceleration() * Square(outside / cost_.impact_acceleration_scale());
  }
  if (!s.kick_touched && scored_this_cycle_) {
    scored_this_cycle_ = false;  // a new cycle
    clearance_ = 1e9;
    cycle_impact_ = std::numeric_limits<double>::quiet_NaN();
  }
  if (!s.kick_touched) clearance_ = std::min(clearance_, BallClearance(env));
  if (r.terminated()) {
    failed_ = true;
    failure_ = cost_.failure() * (2.0 - static_cast<double>(steps_) / horizon_);
    if (!s.kick_touched) failure_ += cost_.miss() * Square(clearance_ / cost_.landing_scale());
    return;
  }
  body_ += BodyCost(env, cost_);
  // The kick is scored at the first step the ball is off the body after a touch (a weak kick
  // that sends it down scores its early crossing).
  if (s.kick_touched && !s.touched_this_step && !scored_this_cycle_) {
    scored_this_cycle_ = true;
    KickOutcome k = PredictKickOutcome(env, anchors_);
    k.impact_acceleration = cycle_impact_;
    if (k.valid) {
      if (kicks_ == 0) first_kick_ = k;
      ++kicks_;
      kick_ += cost_.kick() * (Square(k.timing / cost_.timing_scale_s()) +
                               (Square(k.dx) + Square(k.dy)) / Square(cost_.landing_scale()) +
                               cost_.apex_weight() * Square(k.apex / cost_.apex_scale()));
    }
  }
}

double SoccerRolloutScorer::Finish(const JuggleEnv& env) {
  double total = failure_ + kick_ + impact_cost_ + effort_;
  total += body_ / horizon_;
  if (failed_) return total;
  total += cost_.terminal() * BodyCost(env, cost_);
  if (MissedThisCycle(env)) {
    // The clock has passed this cycle's contact without a touch: the episode will end (the
    // ball is lost, or a late touch breaks the window) just after the horizon. Scored as a
    // failure at the horizon's end, misses ranked by how close the ball came.
    missed_ = true;
    return total + cost_.failure() +
           cost_.miss() * Square(std::min(clearance_, BallClearance(env)) / cost_.landing_scale());
  }
  if (!env.state().kick_touched) {
    const KickOutcome a = PredictApproach(env, anchors_);
    if (a.valid) {
      total += cost_.approach() * (Square(a.timing / cost_.timing_scale_s()) +
                                   (Square(a.dx) + Square(a.dy)) / Square(cost_.landing_scale()));
    }
  }
  return total;
}

}  // namespace juggle::planner
