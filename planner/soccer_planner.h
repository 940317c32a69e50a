// The receding-horizon planner of one soccer env (docs/planner.md): every `replan_every`
// control steps (or once per juggle cycle: PlannerConfig.replan_at_cycle_start) it snapshots
// the env, searches the plan (planner/soccer_plan.h) whose simulated rollout over
// `horizon_steps` costs least (planner/soccer_cost.h) with the cross-entropy method
// (planner/cem_search.h), warm-started from the previous plan shifted to now (or from the
// configured swing: PlannerConfig.cold_start), and then acts with the best plan until the next
// re-plan. The rollouts run the env's own Step on restored copies, so the executed future
// equals the predicted one while nothing outside the plan acts. The planner never changes the
// env it plans for: it only returns actions. Thread-compatible; the pool may be shared by
// planners used one at a time.
#ifndef JUGGLE_PLANNER_SOCCER_PLANNER_H_
#define JUGGLE_PLANNER_SOCCER_PLANNER_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "absl/status/status.h"
#include "common/adaptive_walk.h"
#include "envs/soccer_juggle/env.h"
#include "planner/cem_search.h"
#include "planner/rollout_pool.h"
#include "planner/soccer_cost.h"
#include "planner/soccer_plan.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

// What the last re-plan found (tools, tests, the planner's progress lines).
struct ReplanReport {
  int env_step = 0;            // the env's step count when it re-planned
  double incumbent_cost = 0;   // the warm start's cost
  double best_cost = 0;
  int evaluations = 0;         // rollouts simulated
  bool rescued = false;        // the wider second search ran (PlannerConfig.rescue)
  bool predicts_failure = false;  // the best plan's rollout ends the episode
  Outcome predicted_end = Outcome::kRunning;  // how, and after how many steps
  int predicted_end_step = 0;
  bool predicts_miss = false;  // its horizon ends past a contact its cycle did not make
  KickOutcome predicted_kick;  // the best plan's first kick inside the horizon, if any
  std::vector<double> kick;    // the best plan's kick variables of the current cycle
};

struct PlannerTotals {
  int64_t replans = 0;
  int64_t rollouts = 0;
  int64_t rollout_steps = 0;   // control steps simulated by rollouts
  int64_t rescues = 0;         // re-plans that ran the wider second search
  // Visited states checked against the chosen plan's rollout (position and velocity, bit for
  // bit), and those that differed: the executed future equals the predicted one.
  int64_t prediction_checks = 0;
  int64_t prediction_mismatches = 0;
};

class SoccerPlanner {
 public:
  // `pool` simulates copies of envs of `spec` (REQUIRES: the pool's spec equals `spec`, both
  // outlive the planner). `stream` selects the random stream (e.g. the episode's env index).
  SoccerPlanner(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                const config::PlannerConfig& config, RolloutPool* pool, uint64_t stream);

  // Writes the action for `env`'s current state (kNumActions floats), re-planning first when
  // due. A new episode (the env's step count went back) starts a new plan. Errors: the pool's
  // (a snapshot of another spec).
  absl::Status Act(const soccer_juggle::JuggleEnv& env, float* action);

  // The cost of `theta` from `env`'s current state, and its first predicted kick (tests,
  // tools): the rollout the search runs for one candidate. `draw` d in [1, robust.draws]: with
  // the action noise of the last re-plan's d-th draw (PlannerConfig.robust) instead.
  absl::StatusOr<double> Evaluate(const soccer_juggle::JuggleEnv& env,
                                  const std::vector<double>& theta, KickOutcome* kick = nullptr,
                                  int draw = 0);

  // A copy (plan, warm start, clocks) that draws its searches from random stream `stream` from
  // now on: several re-plans of one state (planner/label_spread.h).
  SoccerPlanner Fork(uint64_t stream) const {
    SoccerPlanner copy = *this;
    copy.stream_ = stream;
    return copy;
  }

  const ReplanReport& last_replan() const { return last_; }
  const PlannerTotals& totals() const { return totals_; }
  const std::vector<double>& plan() const { return theta_; }
  const SoccerPlanLayout& layout() const { return layout_; }

 private:
  // Simulates `theta` from the pool env's restored state; returns its cost.
  // At most this many steps past the horizon to let a kick in contact release the ball.
  static constexpr int kReleaseSteps = 6;
  struct RolloutResult {
    double cost = 0;
    int steps = 0;
    Outcome end = Outcome::kRunning;
    bool missed = false;  // SoccerRolloutScorer::missed
    KickOutcome first_kick;
  };
  // `clock`: where the rollout's first state is in the plan.
  // With `trace`, the fingerprint of the state after every step is appended to it. With
  // config.prune, stops once the cost so far reaches `bound`. `noise`: added to the action of
  // step t from noise[t·kNumActions] on (robust_rows() steps), or none.
  RolloutResult Rollout(soccer_juggle::JuggleEnv* env, const double* theta, PlanClock clock,
                        std::vector<uint64_t>* trace = nullptr,
                        double bound = std::numeric_limits<double>::infinity(),
                        const float* noise = nullptr);
  // PlannerConfig.robust: draws this re-plan's noise (robust_noise_) from random stream
  // (seed, stream, draw_index), and the noise of draw d in [1, draws].
  void DrawRobustNoise(uint64_t draw_index);
  int robust_rows() const { return layout_.horizon + kReleaseSteps; }
  const float* RobustNoise(int draw) const {
    return robust_noise_.data() + size_t(draw - 1) * robust_rows() * soccer_juggle::kNumActions;
  }
  absl::Status Replan(const soccer_juggle::JuggleEnv& env);
  // PlannerConfig.warm_start_from_executed: the plan's map from the current kick set to the
  // action at the state just acted in (RecordActionMap), and the move of that set toward the
  // action that was applied there instead (FollowExecutedAction, at the next state).
  void RecordActionMap(const soccer_juggle::JuggleEnv& env, PlanClock clock, const float* action);
  void FollowExecutedAction(const soccer_juggle::JuggleEnv& env);
  // The kick-consistency cost of `theta` against the previous plan `warm` and its kick prior
  // (PlannerCost.kick_consistency, kick_prior).
  double Regularization(const double* theta, const std::vector<double>& warm) const;
  // Rolls out candidates[i·dim .. (i+1)·dim) for i < n from `snapshot`; counts the steps, and
  // the rollouts of robust draws (the callers count one per candidate). With robust draws a
  // result's cost is the mean over the noiseless rollout and the draws, the rest the
  // noiseless rollout's.
  absl::StatusOr<std::vector<RolloutResult>> RolloutBatch(
      const EnvSnapshot& snapshot, PlanClock clock, const std::vector<double>& candidates, int n,
      double bound = std::numeric_limits<double>::infinity());
  // Gauss-Newton steps on kick set `set`'s variables of `theta` (cost `cost`, regularized
  // against the previous plan `warm`); returns the refined plan and its cost.
  absl::Status Refine(const EnvSnapshot& snapshot, PlanClock clock, int set,
                      const std::vector<double>& warm, std::vector<double>* theta, double* cost);

  std::shared_ptr<const soccer_juggle::JuggleSpec> spec_;
  const config::PlannerConfig config_;
  RolloutPool* pool_;
  uint64_t stream_;
  AdaptiveWalk walk_;
  SoccerPlanLayout layout_;
  SearchSpace space_;
  SearchSpace rescue_space_;  // PlannerConfig.rescue's: every spread widened, body knots free
  CemSettings settings_;
  LandingAnchors anchors_;

  // The plan and where it started.
  std::vector<double> theta_;
  bool has_plan_ = false;
  int origin_step_ = 0;
  int knot0_step_ = 0;  // the episode step of the plan's knot 0
  int origin_cycle_ = 0;
  // The env as last seen: its step count, node and the cycles (DOWN entries) since the reset.
  int last_step_ = -1;
  int last_node_ = -1;
  int cycle_ = 0;
  int64_t replan_count_ = 0;
  // The current re-plan's robust noise: draws × robust_rows() × kNumActions.
  std::vector<float> robust_noise_;
  // The chosen plan's predicted state fingerprints, from origin_step_ + 1 on.
  std::vector<uint64_t> predicted_;
  ReplanReport last_;
  PlannerTotals totals_;
  // The last action's map (RecordActionMap): env step and cycle it was made at, the plan's
  // kick set, the action, and its Jacobian [action][variable] in the set's variables.
  struct ActionMap {
    bool valid = false;
    int step = -1;
    int cycle = -1;
    int set = 0;
    float action[soccer_juggle::kNumActions] = {};
    double jacobian[soccer_juggle::kNumActions][kKickVariables] = {};
  };
  ActionMap action_map_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_PLANNER_H_
