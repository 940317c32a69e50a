// The cost of one soccer rollout (config::SoccerJugglePlanning.cost, docs/planner.md): the episode's end,
// the kicks' predicted free flights, the ball's approach when the horizon ends before the
// kick, the body at every step and at the end, and the effort. Lower is better.
// Thread-compatible: one scorer per rollout thread.
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_COST_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_COST_H_

#include <limits>
#include <string>
#include <vector>

#include "envs/env.h"
#include "envs/soccer_juggle/env.h"
#include "planner/planning_task.h"
#include "planner/soccer_juggle/impact_tracker.h"
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

// The free flight of `env`'s ball from now to the contact node it is headed for (the next
// DOWN node after the current cycle's contact), by the ballistic formula; landings against the
// root.
KickOutcome PredictKickOutcome(const soccer_juggle::JuggleEnv& env);
// The same for a ball still coming down to the current cycle's contact: its crossing of the
// current node's contact height against the nominal contact and the node's ball target.
KickOutcome PredictApproach(const soccer_juggle::JuggleEnv& env);
// A kick outcome as a planning outcome (planner/planning_task.h: timing, dx, dy, apex,
// impact_acceleration; empty when not valid), and back.
std::vector<double> OutcomeValues(const KickOutcome& kick);
KickOutcome KickOutcomeOf(const std::vector<double>& outcome);

// The current cycle's contact has passed without a touch: the node is past its DOWN stage
// (UP) and the ball was not touched in this cycle.
bool MissedThisCycle(const soccer_juggle::JuggleEnv& env);

// The ball's touches in `env`'s current node are a catch or a hold, not a kick: the node is a
// STALL node, or the DOWN node whose contact hands the ball to one.
bool InStall(const soccer_juggle::JuggleEnv& env);

// The stall term at one state (weight × (error/scale)² per PlannerCost.stall): the ball against
// the current STALL node's stall position (the node's ball target from the root, its stall ball
// height) and the ball's speed. 0 outside a STALL node.
double StallCost(const soccer_juggle::JuggleEnv& env, const config::PlannerCost& cost);

// How far (m) the ball's surface is from the nearest geom of a body the current node allows to
// touch it (geom centres less their bounding radii: a ranking, not a collision distance).
double BallClearance(const soccer_juggle::JuggleEnv& env);

// The standing sole's terms at one state (PlannerCost.stance_tilt, stance_turn), summed over
// the standing foot, or both feet when the node swings no leg. Needs mjData's cvel (set by a
// step or mj_forward).
double StanceSoleCost(const soccer_juggle::JuggleEnv& env, const config::PlannerCost& cost);

// Body terms at one state (each already weight × (value/scale)²), StanceSoleCost among them.
double BodyCost(const soccer_juggle::JuggleEnv& env, const config::PlannerCost& cost);

// The cost of a soccer rollout as the driver's scorer. Terms, in order (SoccerTermNames()):
// failure, miss, kick, impact, effort, body, terminal, approach, stall, around_the_world.
class SoccerRolloutScorer final : public RolloutScorer {
 public:
  // `run_on_every_kick`: PlannerConfig.run_on_every_kick (RunsOn).
  SoccerRolloutScorer(const config::PlannerCost& cost, int horizon, bool run_on_every_kick);
  void Begin(const Env& env) override;
  void AfterStep(const Env& env, const float* action, const StepResult& r) override;
  // The total, with the terminal and approach terms of the last state. A last state whose
  // cycle has passed its contact without a touch (MissedThisCycle) costs a failure at the
  // horizon's end (predicts_miss() is then true).
  double Finish(const Env& env) override;
  // The cost so far: never more than the total (every term is non-negative and the per-step
  // body terms are summed over the horizon).
  double partial() const override {
    return failure_ + kick_cost_ + impact_cost_ + effort_ + (body_ + stall_ + around_) / horizon_;
  }
  // A touch that has not yet released the ball runs on (the kick is scored at its release):
  // for any kick, or only for the rollout's first.
  bool RunsOn(const Env& env) const override;
  bool predicts_miss() const override { return missed_; }
  double later_cost() const override { return later_cost_; }
  std::vector<double> first_outcome() const override { return OutcomeValues(first_kick_); }
  std::vector<double> terms() const override;
  std::unique_ptr<RolloutScorer> Clone() const override {
    return std::make_unique<SoccerRolloutScorer>(*this);
  }

  const KickOutcome& first_kick() const { return first_kick_; }
  int kicks() const { return kicks_; }
  bool failed() const { return failed_; }

 private:
  const config::PlannerCost& cost_;
  int horizon_;
  bool run_on_every_kick_;
  int steps_ = 0;
  double body_ = 0, effort_ = 0, kick_cost_ = 0, failure_ = 0;
  double stall_ = 0;  // the stall terms summed over the steps
  double around_ = 0;  // the around-the-world terms summed over the steps
  bool scored_this_cycle_ = false;
  // The closest the ball came to an allowed body in the current cycle before a touch.
  double clearance_ = 1e9;
  ImpactTracker impact_;
  double impact_cost_ = 0;
  double cycle_impact_ = std::numeric_limits<double>::quiet_NaN();  // this cycle's touch
  bool failed_ = false;
  bool missed_ = false;
  int kicks_ = 0;
  double later_cost_ = 0;  // the kick term of kicks after the first
  KickOutcome first_kick_;
  float previous_action_[soccer_juggle::kNumActions] = {0};
  bool has_previous_ = false;
  // For terms() only: the failure and miss parts, and the last state's terms.
  double failure_part_ = 0, miss_part_ = 0, terminal_ = 0, approach_ = 0;
};

// The names of SoccerRolloutScorer::terms(), and of its outcome values.
std::vector<std::string> SoccerTermNames();
std::vector<std::string> KickOutcomeNames();

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_JUGGLE_COST_H_
