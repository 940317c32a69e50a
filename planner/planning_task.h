// The seam between the receding-horizon driver (planner/receding_horizon.h) and what it plans
// for (docs/planner.md, "Adding a planning task"). A PlanningTask says what a plan is (its
// decision variables, their box and spreads, how a warm start shifts), which actions a plan gives
// at a state on top of a prior action, how a rollout is scored (a RolloutScorer with named,
// numbered terms), when a decision cycle starts, and optionally the residuals of a local
// refinement. The driver knows nothing else of the task; a task knows nothing of the search.
// Tasks are immutable after construction and shared by every planner of a run: every method is
// const and thread-safe (rollouts on several threads call them at once). Each env family with a
// task registers it in planner/tasks.cc.
#ifndef JUGGLE_PLANNER_PLANNING_TASK_H_
#define JUGGLE_PLANNER_PLANNING_TASK_H_

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "envs/env.h"
#include "planner/cem_search.h"

namespace juggle::planner {

// Where a visited state is in a plan: control steps since the plan's knot 0 (the decision grid's
// knot at or before its origin) and decision cycles since the plan's origin.
struct PlanClock {
  int step = 0;
  int cycle = 0;
};

// A contiguous block of decision variables (a kick's, a throw's): the refinement and the map
// from variables to actions work on one block at a time. `steps` are the finite-difference steps
// per variable, in the variables' units.
struct VariableBlock {
  int first = 0;
  std::vector<double> steps;
  int size() const { return static_cast<int>(steps.size()); }
};

// The action a plan's offsets are added to (issue 48's learned proposal): zero, or e.g. a policy's
// mean action at the state. Thread-safe: called from every rollout thread.
class ActionPrior {
 public:
  virtual ~ActionPrior() = default;
  // Writes act_dim values for `env`'s current state.
  virtual void Write(const Env& env, double* prior) const = 0;
  // Whether the prior proposes anything (a policy is set): then every re-plan also tries the
  // prior alone, zero offsets, as a candidate (RecedingHorizonPlanner::WarmStart).
  virtual bool proposes() const { return true; }
};

// Scores one rollout: Begin at its first state, AfterStep after every step, Finish at its last.
// Lower is better. One scorer per rollout; thread-compatible.
class RolloutScorer {
 public:
  virtual ~RolloutScorer() = default;
  virtual void Begin(const Env& env) = 0;
  // After each step with its action (act_dim floats, as applied) and result.
  virtual void AfterStep(const Env& env, const float* action, const StepResult& r) = 0;
  // The total, with the terms of the last state.
  virtual double Finish(const Env& env) = 0;
  // The cost so far: never more than the total (pruning stops a rollout once it reaches a bound).
  virtual double partial() const = 0;
  // True when a horizon ending now should run one step further (at most
  // PlanningTask::max_run_on_steps()): e.g. a kick still in contact is scored at its release.
  virtual bool RunsOn(const Env& env) const { return false; }
  // The part of the cost so far that decisions after the rollout's first make (soccer: the
  // kick term of later kicks), which RescueSearch.ignore_later_kicks leaves out of the trouble
  // test. 0: none.
  virtual double later_cost() const { return 0; }
  // The rollout ends past the horizon in a way the task counts as a failure without the episode
  // ending inside it (soccer: a contact passed without a touch). Valid after Finish.
  virtual bool predicts_miss() const { return false; }
  // The first decision's outcome inside the rollout (PlanningTask::outcome_names() values), or
  // empty when none was scored.
  virtual std::vector<double> first_outcome() const { return {}; }
  // The value of every cost term (PlanningTask::term_names() order) after Finish: they add up to
  // the total, up to rounding.
  virtual std::vector<double> terms() const = 0;
  // A copy of this scorer with everything it has seen (PlannerConfig.share_prefix continues
  // every candidate from one scored prefix), or null: the task's rollouts share no prefix.
  virtual std::unique_ptr<RolloutScorer> Clone() const { return nullptr; }
};

class PlanningTask {
 public:
  virtual ~PlanningTask() = default;
  // The env family it plans for ("soccer_juggle").
  virtual std::string family() const = 0;

  // --- Decision variables.
  // The regular search's box and spreads (dim() variables), and the rescue search's.
  virtual const SearchSpace& space() const = 0;
  virtual const SearchSpace& rescue_space() const = 0;
  // The rescue search's space at `env`'s state (football's trap: the pass's part's settings).
  // Default: rescue_space().
  virtual SearchSpace RescueSpaceAt(const Env& env) const { return rescue_space(); }
  int dim() const { return space().dim(); }
  // Control steps a rollout simulates, and at most how many more RolloutScorer::RunsOn may add.
  virtual int horizon() const = 0;
  virtual int max_run_on_steps() const { return 0; }
  // The decision grid: the plan's knot 0 for a plan made at episode step `step`.
  virtual int KnotAtOrBefore(int step) const { return step; }
  // Entering graph node `node` starts a new decision cycle (soccer: a DOWN node).
  virtual bool StartsCycle(const Env& env, int node) const { return false; }
  // The plan re-expressed from later: for a knot 0 `grid_steps` control steps later (a difference
  // of two KnotAtOrBefore values) and `cycles` decision cycles on. REQUIRES: theta.size() ==
  // dim(). The shifted plan acts as the old one did at the states both reach.
  virtual std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                                    int cycles) const = 0;
  // The search's first candidates from the warm start `start` (the first is the incumbent;
  // default: `start` alone).
  virtual std::vector<std::vector<double>> Seeds(const std::vector<double>& start) const {
    return {start};
  }
  // The plan that is the prior alone (the learned proposal without offsets; default: zero).
  virtual std::vector<double> ProposalAlone() const { return std::vector<double>(dim(), 0.0); }
  // How much of the prior plan `theta` takes, in [0, 1] (default: all of it).
  virtual double PriorWeight(const double* theta) const { return 1; }
  // Narrows the search at `env`'s state: e.g. variables that can no longer act are held at the
  // shifted plan's values (`shifted`), in `space` and in every seed; or appends seeds the state
  // suggests (soccer: remembered kicks for the incoming ball). Default: nothing.
  virtual void Restrict(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                        std::vector<std::vector<double>>* seeds) const {}
  // Narrows a rescue search beyond Restrict: fixes variables in `space` and every seed (the
  // rescue's incumbent, seeds[0], included). True when it changed what a candidate simulates
  // (the re-plan's shared prefix no longer applies); default: nothing, false.
  virtual bool RestrictRescue(const Env& env, const std::vector<double>& shifted,
                              SearchSpace* space, std::vector<std::vector<double>>* seeds) const {
    return false;
  }
  // How far (m) the env's ball (or whatever the task's contacts are with) is from a contact
  // that decides the task: PlanningModel.exact_within_m simulates the executed model inside
  // that distance. Default: infinitely far (never).
  virtual double ContactClearance(const Env& env) const {
    return std::numeric_limits<double>::infinity();
  }
  // The plan's own cost beside its rollout's (e.g. consistency with the warm start `warm`, which
  // is the previous plan shifted when `has_warm`, and a prior toward zero). Default: 0.
  virtual double PlanCost(const double* theta, const std::vector<double>& warm,
                          bool has_warm) const {
    return 0;
  }

  // --- Actions.
  // Writes the plan's action at `env`'s state (act_dim floats in [−1, 1]): `prior` (act_dim values,
  // or null for zero) plus the plan's offsets, clamped. REQUIRES: theta holds dim() values.
  virtual void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
                      float* action) const = 0;
  // Whether any decision variable can change Action at `env`'s state and `clock` (theta's fixed
  // variables, which every candidate of a re-plan shares, may decide it). When false, Action
  // must not depend on theta's searched variables: the driver then simulates the steps up to
  // the first where the plan acts once for all candidates (PlannerConfig.share_prefix).
  virtual bool PlanActs(const Env& env, const double* theta, PlanClock clock) const {
    return true;
  }

  // --- Cost.
  virtual std::unique_ptr<RolloutScorer> NewScorer() const = 0;
  // Names of RolloutScorer::terms(), numbered by position.
  virtual std::vector<std::string> term_names() const = 0;
  // Names of RolloutScorer::first_outcome() (empty: the task reports no outcome).
  virtual std::vector<std::string> outcome_names() const { return {}; }

  // --- Optional local refinement (Levenberg–Marquardt on residuals of the first outcome).
  // The block to refine at `env`'s state, or none.
  virtual std::optional<VariableBlock> RefineBlock(const Env& env) const { return std::nullopt; }
  // Residuals of an outcome (num_residuals() values); false when the outcome has none.
  virtual int num_residuals() const { return 0; }
  virtual bool Residuals(const std::vector<double>& outcome, double* residuals) const {
    return false;
  }
  // Weight of the prior rows √w·v/σ_v the refinement adds per variable (0: none).
  virtual double refine_prior_weight() const { return 0; }

  // --- Optional: following an executor's applied action (PlannerConfig.warm_start_from_executed).
  // The block the plan acts through at `clock`, or none.
  virtual std::optional<VariableBlock> ActingBlock(PlanClock clock) const { return std::nullopt; }
  // The action `env` applied at its previous step (act_dim floats), or null.
  virtual const float* AppliedAction(const Env& env) const { return nullptr; }

  // --- Reports.
  // How many of the plan's first variables describe the current decision (reports, label rows).
  virtual int decision_size() const { return 0; }
  // The decision and the first outcome of a re-plan for `--planner-trace` (planner/replan_trace.h),
  // e.g. "  vars ...  kick: ...". Default: each value with its name.
  virtual std::string DescribeDecision(const std::vector<double>& decision,
                                       const std::vector<double>& outcome) const;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNING_TASK_H_
