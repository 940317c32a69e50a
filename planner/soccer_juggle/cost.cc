#include "planner/soccer_juggle/cost.h"

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
KickOutcome OutcomeAt(const JuggleEnv& env, int node, double seconds_to_contact) {
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
  const double root[2] = {d->qpos[0], d->qpos[1]};
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

bool InStall(const JuggleEnv& env) {
  const CursorState& c = env.cursor();
  const ControlGraph& graph = env.spec().graph();
  const config::Stage stage = graph.node(c.current).stage;
  return stage == config::STALL ||
         (stage == config::DOWN && c.next >= 0 && graph.node(c.next).stage == config::STALL);
}

double StallCost(const JuggleEnv& env, const config::PlannerCost& w) {
  const JuggleSpec& spec = env.spec();
  const CursorState& c = env.cursor();
  if (spec.graph().node(c.current).stage != config::STALL) return 0;
  const soccer_juggle::BallReference ref = spec.cursor().DesiredBall(c, c.phase);
  const mjData* d = env.data();
  const double* ball = d->qpos + spec.ball_qpos();
  const double* vel = d->qvel + spec.ball_dof();
  const double error2 = Square(ball[0] - d->qpos[0] - ref.x) +
                        Square(ball[1] - d->qpos[1] - ref.y) + Square(ball[2] - ref.z);
  const double speed2 = Square(vel[0]) + Square(vel[1]) + Square(vel[2]);
  return w.stall() * (error2 / Square(w.stall_scale()) + speed2 / Square(w.stall_speed_scale()));
}

KickOutcome PredictKickOutcome(const JuggleEnv& env) {
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
  return OutcomeAt(env, target, seconds);
}

KickOutcome PredictApproach(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const CursorState& c = env.cursor();
  if (spec.graph().node(c.current).stage != config::DOWN || c.phase_speed <= 0) return {};
  return OutcomeAt(env, c.current, -spec.cursor().SecondsFromContact(c, c.phase));
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

double StanceSoleCost(const JuggleEnv& env, const config::PlannerCost& w) {
  if (w.stance_tilt() == 0 && w.stance_turn() == 0) return 0;
  const JuggleSpec& spec = env.spec();
  const mjData* d = env.data();
  const int right = spec.model()->dof_bodyid[spec.joint(soccer_juggle::kRightAnkle).dof_adr];
  const int left = spec.model()->dof_bodyid[spec.joint(soccer_juggle::kLeftAnkle).dof_adr];
  config::Side swing = config::RIGHT;
  const bool one_foot =
      soccer_juggle::SwingingLeg(spec.graph().node(env.node()).spec.pose(), &swing);
  double sum = 0;
  for (const int foot : {left, right}) {
    if (one_foot && foot == (swing == config::LEFT ? left : right)) continue;
    // The foot's up axis is its local y (y-up joint frames): the rotation matrix's column 1.
    const double tilt = std::acos(std::clamp(d->xmat[9 * foot + 7], -1.0, 1.0));
    const double turn = d->cvel[6 * foot + 2];  // angular velocity about the world's z
    sum += w.stance_tilt() * Square(tilt / w.stance_tilt_scale()) +
           w.stance_turn() * Square(turn / w.stance_turn_scale());
  }
  return sum;
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
  config::Side swing = config::RIGHT;
  if (soccer_juggle::SwingingLeg(pose, &swing)) {
    const int stance = swing == config::LEFT ? right : left;
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
         w.com_speed() * Square(speed / w.com_speed_scale()) + StanceSoleCost(env, w);
}

std::vector<double> OutcomeValues(const KickOutcome& k) {
  if (!k.valid) return {};
  return {k.timing, k.dx, k.dy, k.apex, k.impact_acceleration};
}

KickOutcome KickOutcomeOf(const std::vector<double>& v) {
  KickOutcome k;
  if (v.size() != 5) return k;
  k.valid = true;
  k.timing = v[0];
  k.dx = v[1];
  k.dy = v[2];
  k.apex = v[3];
  k.impact_acceleration = v[4];
  return k;
}

std::vector<std::string> KickOutcomeNames() {
  return {"timing_s", "landing_dx_m", "landing_dy_m", "apex_m", "impact_acceleration"};
}

std::vector<std::string> SoccerTermNames() {
  return {"failure", "miss",     "kick",     "impact", "effort", "body",
          "terminal", "approach", "stall", "around_the_world"};
}

SoccerRolloutScorer::SoccerRolloutScorer(const config::PlannerCost& cost, int horizon,
                                         bool run_on_every_kick)
    : cost_(cost), horizon_(std::max(horizon, 1)), run_on_every_kick_(run_on_every_kick) {}

void SoccerRolloutScorer::Begin(const Env& base) {
  const auto& env = static_cast<const JuggleEnv&>(base);
  // A kick whose ball is already on its way was scored by an earlier plan; one whose ball is
  // still on the body is this plan's to score.
  scored_this_cycle_ =
      env.state().kick_touched && !env.state().touched_this_step && !InStall(env);
  impact_.Begin(env);
}

bool SoccerRolloutScorer::RunsOn(const Env& base) const {
  const auto& env = static_cast<const JuggleEnv&>(base);
  const bool in_contact =
      env.state().kick_touched && env.state().touched_this_step && !scored_this_cycle_;
  return in_contact && !InStall(env) && (run_on_every_kick_ || kicks_ == 0);
}

void SoccerRolloutScorer::AfterStep(const Env& base, const float* action, const StepResult& r) {
  const auto& env = static_cast<const JuggleEnv&>(base);
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
    failure_part_ = failure_;
    if (!s.kick_touched) {
      miss_part_ = cost_.miss() * Square(clearance_ / cost_.landing_scale());
      failure_ += miss_part_;
    }
    return;
  }
  body_ += BodyCost(env, cost_);
  stall_ += StallCost(env, cost_);
  around_ += cost_.around_the_world() * env.AroundTheWorldViolation();
  // The kick is scored at the first step the ball is off the body after a touch (a weak kick
  // that sends it down scores its early crossing); a ball off the body in a stall is not one.
  if (s.kick_touched && !s.touched_this_step && !scored_this_cycle_ && !InStall(env)) {
    scored_this_cycle_ = true;
    KickOutcome k = PredictKickOutcome(env);
    k.impact_acceleration = cycle_impact_;
    if (k.valid) {
      if (kicks_ == 0) first_kick_ = k;
      const double weight = kicks_ == 0 ? 1.0 : cost_.later_kicks();
      ++kicks_;
      const double term =
          weight * cost_.kick() *
          (Square(k.timing / cost_.timing_scale_s()) +
           (Square(k.dx) + Square(k.dy)) / Square(cost_.landing_scale()) +
           cost_.apex_weight() * Square(k.apex / cost_.apex_scale()));
      kick_cost_ += term;
      if (kicks_ > 1) later_cost_ += term;
    }
  }
}

double SoccerRolloutScorer::Finish(const Env& base) {
  const auto& env = static_cast<const JuggleEnv&>(base);
  double total = failure_ + kick_cost_ + impact_cost_ + effort_;
  total += (body_ + stall_ + around_) / horizon_;
  if (failed_) return total;
  terminal_ = cost_.terminal() * BodyCost(env, cost_);
  total += terminal_;
  if (MissedThisCycle(env)) {
    // The clock has passed this cycle's contact without a touch: the episode will end (the
    // ball is lost, or a late touch breaks the window) just after the horizon. Scored as a
    // failure at the horizon's end, misses ranked by how close the ball came.
    missed_ = true;
    failure_part_ = cost_.failure();
    miss_part_ =
        cost_.miss() * Square(std::min(clearance_, BallClearance(env)) / cost_.landing_scale());
    return total + failure_part_ + miss_part_;
  }
  if (!env.state().kick_touched) {
    const KickOutcome a = PredictApproach(env);
    if (a.valid) {
      approach_ = cost_.approach() * (Square(a.timing / cost_.timing_scale_s()) +
                                      (Square(a.dx) + Square(a.dy)) / Square(cost_.landing_scale()));
      total += approach_;
    }
  }
  return total;
}

std::vector<double> SoccerRolloutScorer::terms() const {
  return {failure_part_, miss_part_, kick_cost_, impact_cost_, effort_, body_ / horizon_,
          terminal_, approach_, stall_ / horizon_, around_ / horizon_};
}

}  // namespace juggle::planner
