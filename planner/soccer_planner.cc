#include "planner/soccer_planner.h"

#include <algorithm>

#include "common/check.h"

namespace juggle::planner {

using soccer_juggle::JuggleEnv;
using soccer_juggle::kNumActions;

SoccerPlanner::SoccerPlanner(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                             const config::PlannerConfig& config, RolloutPool* pool,
                             uint64_t stream)
    : spec_(std::move(spec)),
      config_(config),
      pool_(pool),
      stream_(stream),
      walk_(&spec_->graph()),
      layout_(MakeSoccerPlanLayout(config_)),
      space_(MakeSoccerSearchSpace(layout_, config_)) {
  settings_.samples = config_.samples();
  settings_.iterations = config_.iterations();
  settings_.elite_fraction = config_.elite_fraction();
  settings_.keep_elite_fraction = config_.keep_elite_fraction();
  settings_.min_sigma_fraction = config_.min_sigma_fraction();
  theta_.assign(layout_.dim(), 0.0);
}

SoccerPlanner::RolloutResult SoccerPlanner::Rollout(JuggleEnv* env, const double* theta,
                                                    PlanClock clock) {
  RolloutResult result;
  SoccerRolloutScorer scorer(config_.cost(), layout_.horizon);
  scorer.Begin(*env);
  float action[kNumActions];
  int node = env->node();
  int t = 0;
  for (; t < layout_.horizon; ++t, ++clock.step) {
    SoccerPlanAction(*env, layout_, theta, clock, action);
    const StepResult r = env->Step(action, walk_);
    scorer.AfterStep(*env, action, r);
    if (r.outcome != Outcome::kRunning) {
      result.end = r.outcome;
      ++t;
      break;
    }
    if (env->node() != node) {
      node = env->node();
      if (spec_->graph().node(node).stage == config::DOWN) ++clock.cycle;
    }
  }
  result.first_kick = scorer.first_kick();
  result.steps = t;
  result.cost = scorer.Finish(*env);
  return result;
}

absl::StatusOr<double> SoccerPlanner::Evaluate(const JuggleEnv& env,
                                               const std::vector<double>& theta,
                                               KickOutcome* kick) {
  JUGGLE_CHECK(static_cast<int>(theta.size()) == layout_.dim(), "plan of the wrong size");
  const std::unique_ptr<EnvSnapshot> snapshot = env.Snapshot();
  double cost = 0;
  absl::Status s = pool_->Run(*snapshot, 1, [&](int, Env* copy) {
    const PlanClock clock{env.steps() - KnotAtOrBefore(layout_, env.steps()), 0};
    const RolloutResult r = Rollout(static_cast<JuggleEnv*>(copy), theta.data(), clock);
    cost = r.cost;
    if (kick != nullptr) *kick = r.first_kick;
  });
  if (!s.ok()) return s;
  return cost;
}

absl::Status SoccerPlanner::Replan(const JuggleEnv& env) {
  const int knot0 = KnotAtOrBefore(layout_, env.steps());
  const int moved = layout_.knot_steps > 0 ? (knot0 - knot0_step_) / layout_.knot_steps : 0;
  const std::vector<double> start = has_plan_
                                        ? ShiftSoccerPlan(layout_, theta_, moved, cycle_ - origin_cycle_)
                                        : std::vector<double>(layout_.dim(), 0.0);
  const PlanClock clock{env.steps() - knot0, 0};
  const std::unique_ptr<EnvSnapshot> snapshot = env.Snapshot();
  Rng rng = Rng::ForStream(config_.seed(), stream_, static_cast<uint64_t>(replan_count_++));
  absl::Status status;
  const int dim = layout_.dim();
  std::vector<int> steps;
  const BatchCost cost = [&](const std::vector<double>& candidates, int n,
                             std::vector<double>* costs) {
    steps.assign(n, 0);
    absl::Status s = pool_->Run(*snapshot, n, [&](int i, Env* copy) {
      const RolloutResult r =
          Rollout(static_cast<JuggleEnv*>(copy), candidates.data() + i * dim, clock);
      (*costs)[i] = r.cost;
      steps[i] = r.steps;
    });
    if (!s.ok()) {
      status = s;
      std::fill(costs->begin(), costs->end(), 0.0);
      return;
    }
    for (int x : steps) totals_.rollout_steps += x;
  };
  // Seeds: the shifted plan, and the same with the nominal kick (a carried kick that no longer
  // fits is then one candidate away from the configured swing).
  std::vector<std::vector<double>> seeds = {start};
  if (layout_.kick_sets > 0) {
    seeds.push_back(start);
    std::fill(seeds.back().begin(), seeds.back().begin() + layout_.kick_dim(), 0.0);
  }
  const CemResult result = MinimizeCem(space_, settings_, seeds, &rng, cost);
  if (!status.ok()) return status;
  theta_ = result.best;
  has_plan_ = true;
  origin_step_ = env.steps();
  knot0_step_ = knot0;
  origin_cycle_ = cycle_;
  ++totals_.replans;
  totals_.rollouts += result.evaluations;
  last_.env_step = env.steps();
  last_.incumbent_cost = result.incumbent_cost;
  last_.best_cost = result.best_cost;
  last_.evaluations = result.evaluations;
  // The chosen plan's prediction, for reports (one more rollout).
  RolloutResult chosen;
  status = pool_->Run(*snapshot, 1, [&](int, Env* copy) {
    chosen = Rollout(static_cast<JuggleEnv*>(copy), theta_.data(), clock);
  });
  ++totals_.rollouts;
  totals_.rollout_steps += chosen.steps;
  last_.predicted_kick = chosen.first_kick;
  last_.kick.assign(theta_.begin(), theta_.begin() + std::min(kKickVariables, layout_.kick_dim()));
  last_.predicted_end = chosen.end;
  last_.predicted_end_step = env.steps() + chosen.steps;
  last_.predicts_failure = chosen.end != Outcome::kRunning && chosen.end != Outcome::kTimeLimit;
  return status;
}

absl::Status SoccerPlanner::Act(const JuggleEnv& env, float* action) {
  if (env.steps() <= last_step_ || last_step_ < 0) {
    // A new episode.
    has_plan_ = false;
    cycle_ = 0;
    last_node_ = env.node();
  } else if (env.node() != last_node_) {
    last_node_ = env.node();
    if (spec_->graph().node(last_node_).stage == config::DOWN) ++cycle_;
  }
  last_step_ = env.steps();
  if (!has_plan_ || env.steps() - origin_step_ >= config_.replan_every()) {
    if (absl::Status s = Replan(env); !s.ok()) return s;
  }
  PlanClock clock{env.steps() - knot0_step_, cycle_ - origin_cycle_};
  SoccerPlanAction(env, layout_, theta_.data(), clock, action);
  return absl::OkStatus();
}

}  // namespace juggle::planner
