// The cost of one soccer rollout (config::PlannerCost, docs/planner.md): the episode's end,
// the kicks' predicted free flights, the ball's approach when the horizon ends before the
// kick, the body at every step and at the end, and the effort. Lower is better.
// Thread-compatible: one scorer per rollout thread.
#ifndef JUGGLE_PLANNER_SOCCER_COST_H_
#define JUGGLE_PLANNER_SOCCER_COST_H_

#include <array>
#include <limits>
#include <vector>

#include "envs/env.h"
#include "envs/soccer_juggle/env.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

// What a kick sends the ball to: its errors against the next contact (s, m, m).
struct KickOutcome {
  bool valid = false;   // false: the ball is not on a flight to a contact node
  double timing = 0;    // crossing of the contact height minus the nominal contact (s)
  double dx = 0, dy = 0;  // crossing point minus root + ball target (m, world axes)
  double apex = 0;      // apex minus the node's apex height (m)
  // The kicking body's acceleration along the kick's impulse just before the touch (m/s²,
  // ImpactTracker); NaN when not measured.
  double impact_acceleration = std::numeric_limits<double>::quiet_NaN();
};

// Where a landing is measured from. The node's ball target is relative to the root; with
// `stance` set, the root's place is taken as the stance foot's now plus where the root sits
// over that foot in the node's reference pose at the contact (a foot planted on the ground
// moves less than a swaying pelvis).
struct LandingAnchors {
  bool stance = false;
  // Per graph node: root minus stance ankle (x, y) in the reference pose at φ = 0.5, and the
  // stance ankle's body id (−1: no leg swing, the root is the anchor).
  std::vector<std::array<double, 2>> root_from_stance;
  std::vector<int> stance_body;
};
// The anchors of every node of `spec`'s graph (the reference poses' kinematics).
LandingAnchors MakeLandingAnchors(const soccer_juggle::JuggleSpec& spec, bool stance);

// The free flight of `env`'s ball from now to the contact node it is headed for (the next
// DOWN node after the current cycle's contact), by the ballistic formula. `anchors` may be
// null (the root).
KickOutcome PredictKickOutcome(const soccer_juggle::JuggleEnv& env,
                               const LandingAnchors* anchors = nullptr);
// The same for a ball still coming down to the current cycle's contact: its crossing of the
// current node's contact height against the nominal contact and the node's ball target.
KickOutcome PredictApproach(const soccer_juggle::JuggleEnv& env,
                            const LandingAnchors* anchors = nullptr);

// The current cycle's contact has passed without a touch: the node is past its DOWN stage
// (UP) and the ball was not touched in this cycle.
bool MissedThisCycle(const soccer_juggle::JuggleEnv& env);

// How far (m) the ball's surface is from the nearest geom of a body the current node allows to
// touch it (geom centres less their bounding radii: a ranking, not a collision distance).
double BallClearance(const soccer_juggle::JuggleEnv& env);

// How the body that kicks moved into the ball: at a cycle's first touch, its centre of mass's
// acceleration along the direction of the ball's velocity change (the impulse; gravity and the
// env's ball force taken out) over the control step before the touch (docs/planner.md,
// "Impact acceleration"). Negative: the foot decelerates into the ball, which damps apex
// errors from kick to kick. The touching body is the env's (JuggleEnvState.touched_body). A
// touch in the first step after Begin is measured against the velocities one step back at the
// first state's acceleration. A cycle already touched at Begin, or whose touch comes in the
// same step as its DOWN node, is not measured.
class ImpactTracker {
 public:
  // At the first state.
  void Begin(const soccer_juggle::JuggleEnv& env);
  // After each step: the acceleration (m/s²) when this step holds a cycle's first touch; NaN
  // otherwise.
  double AfterStep(const soccer_juggle::JuggleEnv& env);

 private:
  // The tracked bodies' centre-of-mass velocities (3 per body, world axes) at `qvel`.
  void BodyVelocities(const soccer_juggle::JuggleEnv& env, const double* qvel,
                      std::vector<double>* out);
  // The bodies some node allows to touch the ball, and their velocities one and two steps back.
  std::vector<int> bodies_;
  std::vector<double> velocity_[2];
  std::vector<double> jacobian_;  // scratch, 3 × nv
  double ball_velocity_[3] = {0, 0, 0};  // one step back
  bool was_touched_ = false;
};

// Body terms at one state (each already weight × (value/scale)²).
double BodyCost(const soccer_juggle::JuggleEnv& env, const config::PlannerCost& cost);

class SoccerRolloutScorer {
 public:
  // `anchors` may be null (landings against the root) and must outlive the scorer.
  SoccerRolloutScorer(const config::PlannerCost& cost, int horizon,
                      const LandingAnchors* anchors = nullptr);
  // At the rollout's first state.
  void Begin(const soccer_juggle::JuggleEnv& env);
  // After each step with its action ([kNumActions]) and result.
  void AfterStep(const soccer_juggle::JuggleEnv& env, const float* action, const StepResult& r);
  // The total, with the terminal and approach terms of the last state. A last state whose
  // cycle has passed its contact without a touch (MissedThisCycle) costs a failure at the
  // horizon's end (missed() is then true).
  double Finish(const soccer_juggle::JuggleEnv& env);
  bool missed() const { return missed_; }
  // A touch that has not yet released the ball (the kick is scored at its release).
  bool kick_in_contact(const soccer_juggle::JuggleEnv& env) const {
    return env.state().kick_touched && env.state().touched_this_step && !scored_this_cycle_;
  }
  // The cost so far: never more than the total (every term is non-negative and the per-step
  // body terms are summed over the horizon).
  double partial() const { return failure_ + kick_ + impact_cost_ + effort_ + body_ / horizon_; }
  // The kick outcomes scored (the first one), for tests and tools.
  const KickOutcome& first_kick() const { return first_kick_; }
  int kicks() const { return kicks_; }
  bool failed() const { return failed_; }

 private:
  const config::PlannerCost& cost_;
  int horizon_;
  const LandingAnchors* anchors_;
  int steps_ = 0;
  double body_ = 0, effort_ = 0, kick_ = 0, failure_ = 0;
  bool scored_this_cycle_ = false;
  // The closest the ball came to an allowed body in the current cycle before a touch.
  double clearance_ = 1e9;
  ImpactTracker impact_;
  double impact_cost_ = 0;
  double cycle_impact_ = std::numeric_limits<double>::quiet_NaN();  // this cycle's touch
  bool failed_ = false;
  bool missed_ = false;
  int kicks_ = 0;
  KickOutcome first_kick_;
  float previous_action_[soccer_juggle::kNumActions] = {0};
  bool has_previous_ = false;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_COST_H_
