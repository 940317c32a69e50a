// The receding-horizon planner of one env, for any PlanningTask (planner/planning_task.h;
// docs/planner.md): every `replan_every` control steps (or once per decision cycle:
// PlannerConfig.replan_at_cycle_start) it snapshots the env, searches the plan whose simulated
// rollout costs least with the cross-entropy method (planner/cem_search.h), warm-started from the
// previous plan shifted to now (or from zero: PlannerConfig.cold_start), searches again wider
// when the best plan costs too much (PlannerConfig.rescue), optionally refines it, and then acts
// with it until the next re-plan. The rollouts run the env's own Step on restored copies, so the
// executed future equals the predicted one while nothing outside the plan acts: every visited
// state is checked against the prediction, bit for bit. The planner never changes the env it
// plans for: it only returns actions. Thread-compatible; the pool may be shared by planners used
// one at a time.
#ifndef JUGGLE_PLANNER_RECEDING_HORIZON_H_
#define JUGGLE_PLANNER_RECEDING_HORIZON_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/adaptive_walk.h"
#include "planner/cem_search.h"
#include "planner/planning_task.h"
#include "planner/rescue_sample_log.h"
#include "planner/rollout_pool.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

// What the last re-plan found (tools, tests, the planner's progress lines).
struct ReplanReport {
  int env_step = 0;            // the env's step count when it re-planned
  int node = 0;                // the env's graph node then (Env::node)
  double incumbent_cost = 0;   // the warm start's cost
  double best_cost = 0;
  // Candidates scored; a few may be read from this re-plan's own earlier rollouts
  // (PlannerTotals.rollouts counts only the simulated ones).
  int evaluations = 0;
  bool rescued = false;        // the wider second search ran (PlannerConfig.rescue)
  bool refined_out = false;    // in trouble, and the refinement before the rescue fixed it
  bool light = false;          // the warm start kept without a search (search_skip_below)
  bool predicts_failure = false;  // the best plan's rollout ends the episode
  Outcome predicted_end = Outcome::kRunning;  // how, and after how many steps
  int predicted_end_step = 0;
  bool predicts_miss = false;  // RolloutScorer::predicts_miss of the best plan's rollout
  // The best plan's first outcome (PlanningTask::outcome_names(); empty: none) and its cost
  // terms (PlanningTask::term_names()).
  std::vector<double> predicted_outcome;
  std::vector<double> terms;
  // The best plan's first PlanningTask::decision_size() variables.
  std::vector<double> decision;
};

struct PlannerTotals {
  int64_t replans = 0;
  int64_t rollouts = 0;
  int64_t rollout_steps = 0;   // control steps simulated by rollouts
  int64_t rescues = 0;         // re-plans that ran the wider second search
  int64_t rescue_rollout_steps = 0;  // the part of rollout_steps the rescues simulated
  // Re-plans that simulated their warm start alone and kept it (PlannerConfig.search_skip_below).
  int64_t light_replans = 0;
  // Re-plans in trouble that the refinement before the rescue (RescueSearch.refine_first)
  // brought out of it, so no rescue ran.
  int64_t refined_out_of_trouble = 0;
  // Decayed rescues still in trouble that a full one followed (RescueSearch.full_after_decay).
  int64_t full_after_decay = 0;
  // Narrowed rescues still in trouble that an unnarrowed one followed
  // (RescueSearch.full_after_narrowed).
  int64_t full_after_narrowed = 0;
  // Rescues of half-fixed re-plans: the best plan in trouble only by RescueSearch.half_fixed_above
  // (below cost_above after a troubled warm start).
  int64_t half_fixed_rescues = 0;
  // Troubled re-plans that ran no rescue after one that still predicted the episode's end
  // (RescueSearch.pause_after_lost).
  int64_t rescues_paused = 0;
  // With a proposing prior (PlannerConfig.policy_prior and a policy set): re-plans that tried
  // the proposal alone (zero offsets) as a candidate, and those that chose it (the policy's
  // share of chosen candidates, issue 48).
  int64_t proposal_tried = 0;
  int64_t proposal_chosen = 0;
  // Over the re-plans that tried it: the chosen plans' weight of the prior (PriorWeight: 1
  // unless the trust is searched, PlannerConfig.search_prior_trust), summed.
  double proposal_weight_sum = 0;
  // Visited states checked against the chosen plan's rollout (position and velocity, bit for
  // bit), and those that differed: the executed future equals the predicted one.
  int64_t prediction_checks = 0;
  int64_t prediction_mismatches = 0;
  // With a planning model (PlannerConfig.planning_model): rollouts and control steps on the
  // executed model (not in rollouts / rollout_steps); re-plans whose choice was simulated on
  // both models; those the two judged differently (a failure or a missed contact predicted by
  // one only); those where the warm start acted because it cost less on the executed model;
  // and the chosen plans' cost on the executed model minus on the planning model, summed.
  int64_t exact_rollouts = 0;
  int64_t exact_rollout_steps = 0;
  int64_t model_checks = 0;
  int64_t model_disagreements = 0;
  int64_t model_overrides = 0;
  double model_cost_gap_sum = 0;
  void Add(const PlannerTotals& other);
};

class RecedingHorizonPlanner {
 public:
  // `pool` simulates copies of envs of the task's family (REQUIRES: the pool's spec is the one
  // the task was made for; the pool outlives the planner). `stream` selects the random stream
  // (e.g. the episode's env index). `prior`, if not null, is the action the plan's offsets are
  // added to (must outlive the planner). `exact_pool`, with a planning model (`pool` simulating
  // PlannerConfig.planning_model): a pool on the executed model, where the chosen plan is
  // simulated again (its prediction, and PlanningModel.check_on_exact).
  RecedingHorizonPlanner(std::shared_ptr<const PlanningTask> task,
                         const config::PlannerConfig& config, RolloutPool* pool, uint64_t stream,
                         const ActionPrior* prior = nullptr, RolloutPool* exact_pool = nullptr);

  // Writes the action for `env`'s current state (act_dim floats), re-planning first when due. A
  // new episode (the env's step count went back) starts a new plan. Errors: the pool's (a
  // snapshot of another spec).
  absl::Status Act(const Env& env, float* action);

  // The cost of `theta` from `env`'s current state, and its first outcome (tests, tools): the
  // rollout the search runs for one candidate. `draw` d in [1, robust.draws]: with the action
  // noise of the last re-plan's d-th draw (PlannerConfig.robust) instead.
  absl::StatusOr<double> Evaluate(const Env& env, const std::vector<double>& theta,
                                  std::vector<double>* outcome = nullptr, int draw = 0);

  // A copy (plan, warm start, clocks) that draws its searches from random stream `stream` from
  // now on: several re-plans of one state (planner/label_spread.h).
  RecedingHorizonPlanner Fork(uint64_t stream) const {
    RecedingHorizonPlanner copy = *this;
    copy.stream_ = stream;
    return copy;
  }

  // Every rollout of the rescue searches from now on is written to `log` (null: none; it must
  // outlive the planner and its forks): planner/rescue_sample_log.h.
  void set_rescue_log(RescueSampleLog* log) { rescue_log_ = log; }

  const ReplanReport& last_replan() const { return last_; }
  const PlannerTotals& totals() const { return totals_; }
  const std::vector<double>& plan() const { return theta_; }
  const PlanningTask& task() const { return *task_; }

 private:
  struct RolloutResult {
    double cost = 0;
    int steps = 0;
    Outcome end = Outcome::kRunning;
    bool missed = false;  // RolloutScorer::predicts_miss
    int exact_steps = 0;  // of `steps`, simulated on the executed model (exact_within_m)
    int shared_steps = 0;  // of `steps`, the shared prefix's (simulated once per re-plan)
    std::vector<double> first_outcome;
    std::vector<double> terms;  // only when asked for (the chosen plan's rollout)
    double later = 0;     // RolloutScorer::later_cost
    bool pruned = false;  // stopped at the bound: `cost` is its cost so far
  };
  // How a rollout runs: the plan's clock at its first state; with `trace`, the fingerprint of
  // the state after each of the first `trace_steps` steps is appended to it; with config.prune
  // it stops once the cost so far reaches `bound`; `noise`: added to the action of step t from
  // noise[t·act_dim] on (robust_rows() steps), or none.
  struct SharedPrefix;  // below
  struct RolloutOptions {
    PlanClock clock;
    std::vector<uint64_t>* trace = nullptr;
    int trace_steps = std::numeric_limits<int>::max();
    double bound = std::numeric_limits<double>::infinity();
    const float* noise = nullptr;
    bool terms = false;
    // Continue from this prefix's end (the env already holds its state) instead of the start.
    const SharedPrefix* prefix = nullptr;
  };
  // PlannerConfig.share_prefix: the steps from a re-plan's state up to the first where the plan
  // acts (PlanningTask::PlanActs), simulated once; `state` null when there are none to share.
  struct SharedPrefix {
    std::unique_ptr<EnvSnapshot> state;
    std::unique_ptr<RolloutScorer> scorer;
    int steps = 0;
    PlanClock clock;              // at its end
    int node = 0;                 // the env's node at its end
    double max_partial = 0;       // the largest cost so far after any of its steps
    std::vector<uint64_t> trace;  // the state fingerprints of its steps
  };
  // What one re-plan works on: the snapshot of the state, its clock, the previous plan shifted
  // to now, the search's seeds and space, and its random stream.
  struct ReplanState;
  // A noiseless rollout of the current re-plan that ran to its end: the chosen plan's
  // prediction and InTrouble's measure are read from it instead of simulated again (the
  // simulation is deterministic: a second rollout of `theta` would give the same).
  struct SeenRollout {
    std::vector<double> theta;
    RolloutResult result;         // with its terms
    std::vector<uint64_t> trace;  // its first TracedSteps() state fingerprints
  };
  // The fingerprints a prediction needs: the most steps a plan acts before the next re-plan.
  int TracedSteps() const;
  // The current re-plan's rollout of `theta`, or null if none ran to its end.
  const SeenRollout* Seen(const std::vector<double>& theta) const;

  // Simulates `theta` from `env`'s restored state.
  RolloutResult Rollout(Env* env, const double* theta, const RolloutOptions& options) const;
  // Rolls out candidates[i·dim .. (i+1)·dim) for i < n from `snapshot`; counts the steps, and the
  // rollouts of robust draws (the callers count one per candidate). With robust draws a result's
  // cost is the mean over the noiseless rollout and the draws, the rest the noiseless rollout's.
  absl::StatusOr<std::vector<RolloutResult>> RolloutBatch(
      const EnvSnapshot& snapshot, PlanClock clock, const std::vector<double>& candidates, int n,
      double bound = std::numeric_limits<double>::infinity());
  // The re-plan's shared prefix from `snapshot` at `clock` (computed on first use, simulating
  // `theta`'s actions, which no variable changes there), or null: none, or not usable for a
  // bound of `bound` (a rollout would stop inside it).
  const SharedPrefix* PrefixFor(const EnvSnapshot& snapshot, PlanClock clock,
                                const double* theta, double bound);
  // The search's cost: each candidate's rollout plus the task's plan cost.
  absl::Status ScoreBatch(const ReplanState& r, const std::vector<double>& candidates, int n,
                          double bound, std::vector<double>* costs);

  // The steps of a re-plan, in order.
  absl::Status Replan(const Env& env);
  ReplanState WarmStart(const Env& env);
  absl::StatusOr<CemResult> Search(ReplanState& r);
  absl::Status Rescue(const Env& env, ReplanState& r, CemResult* result);
  // Whether `result`'s best plan is in trouble: above `above` (> 0), and with
  // RescueSearch.ignore_later_kicks also its cost less the later kicks' (one more rollout).
  // `measure` (optional): the cost compared with `above` when in trouble.
  absl::StatusOr<bool> InTrouble(const ReplanState& r, const CemResult& result, double above,
                                 double* measure = nullptr);
  absl::Status RefineBest(const Env& env, ReplanState& r, CemResult* result);
  // `iterations` refinement steps (Refine) on the task's block for `env` (RefineBlock) of
  // result's best plan, in place; nothing when the task has no block here.
  absl::Status RefineNextKick(const Env& env, const ReplanState& r, int iterations,
                              CemResult* result);
  absl::Status Commit(const Env& env, const ReplanState& r, const CemResult& result);
  // With a planning model: simulates theta_ (the planning model's choice) on it once more and,
  // beside the warm start (PlanningModel.check_on_exact), on the executed model; counts the
  // comparison, keeps whichever of the two costs less there in theta_, and returns its
  // executed-model rollout with its prediction in predicted_.
  absl::Status ChooseOnExact(const ReplanState& r, bool had_plan, RolloutResult* chosen);

  // `iterations` Levenberg–Marquardt steps on `block` of `theta` (cost `cost`, plan cost
  // against `warm`); keeps a step only if the whole cost falls.
  absl::Status Refine(const EnvSnapshot& snapshot, PlanClock clock, const VariableBlock& block,
                      const std::vector<double>& warm, int iterations, std::vector<double>* theta,
                      double* cost);

  // PlannerConfig.robust: draws this re-plan's noise (robust_noise_) from random stream
  // (seed, stream, draw_index), and the noise of draw d in [1, draws].
  void DrawRobustNoise(uint64_t draw_index);
  int robust_rows() const { return task_->horizon() + task_->max_run_on_steps(); }
  const float* RobustNoise(int draw) const {
    return robust_noise_.data() + size_t(draw - 1) * robust_rows() * act_dim_;
  }

  // PlannerConfig.warm_start_from_executed: the plan's map from the acting block to the action
  // at the state just acted in (RecordActionMap), and the move of that block toward the action
  // that was applied there instead (FollowExecutedAction, at the next state).
  void RecordActionMap(const Env& env, PlanClock clock, const float* action);
  void FollowExecutedAction(const Env& env);

  // Follows the env's decision cycles (a new episode, a node that starts a cycle).
  void TrackCycles(const Env& env);
  // Counts the visited state against the chosen plan's prediction.
  void CheckPrediction(const Env& env);

  std::shared_ptr<const PlanningTask> task_;
  config::PlannerConfig config_;
  RolloutPool* pool_;
  RolloutPool* exact_pool_;  // null: the rollouts run on the executed model
  // The current re-plan's shared prefix once computed (reset by WarmStart; a Fork shares it
  // until its own next re-plan).
  std::shared_ptr<SharedPrefix> prefix_;
  uint64_t stream_;
  const ActionPrior* prior_;
  int act_dim_;
  AdaptiveWalk walk_;
  CemSettings settings_;

  // The plan and where it started.
  std::vector<double> theta_;
  bool has_plan_ = false;
  int origin_step_ = 0;
  int knot0_step_ = 0;  // the episode step of the plan's knot 0
  int origin_cycle_ = 0;
  // The env as last seen: its step count, node and the decision cycles since the reset.
  int last_step_ = -1;
  int last_node_ = -1;
  int cycle_ = 0;
  int64_t replan_count_ = 0;
  // Control steps from this plan's origin to the next re-plan (PlannerConfig.replan_every_max).
  int interval_ = 0;
  // Re-plans in a row whose regular search ended above the rescue's threshold.
  int troubled_ = 0;
  // Re-plans left that run no rescue (RescueSearch.pause_after_lost).
  int rescue_pause_ = 0;
  // Light re-plans in a row since the last search (PlannerConfig.search_every).
  int light_streak_ = 0;
  // Re-plans since the last rescue (0 after the rescue's own; a re-plan's count for
  // PlannerConfig.light_from is this + 1).
  int since_rescue_ = kNoRescueYet;
  static constexpr int kNoRescueYet = 1 << 30;
  // The current re-plan's robust noise: draws × robust_rows() × act_dim.
  std::vector<float> robust_noise_;
  // The chosen plan's predicted state fingerprints, from origin_step_ + 1 on (TracedSteps).
  std::vector<uint64_t> predicted_;
  // The current re-plan's rollouts (reset by WarmStart), and the snapshot they start from.
  std::vector<SeenRollout> seen_;
  const EnvSnapshot* seen_from_ = nullptr;
  ReplanReport last_;
  PlannerTotals totals_;
  RescueSampleLog* rescue_log_ = nullptr;
  int logged_rescue_ = 0;  // the rescue whose rollouts ScoreBatch writes to rescue_log_; 0: none
  // The last action's map (RecordActionMap): env step and cycle it was made at, the acting
  // block, the action, and its Jacobian [action][variable] in the block's variables.
  struct ActionMap {
    bool valid = false;
    int step = -1;
    int cycle = -1;
    VariableBlock block;
    std::vector<float> action;
    std::vector<double> jacobian;  // act_dim × block.size(), row-major
  };
  ActionMap action_map_;
};

// FNV-1a of an env's positions and velocities (the prediction check's fingerprint).
uint64_t StateFingerprint(const Env& env, const mjModel* m);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_RECEDING_HORIZON_H_
