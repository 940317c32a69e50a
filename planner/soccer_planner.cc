#include "planner/soccer_planner.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "common/status_macros.h"

namespace juggle::planner {
namespace {

// FNV-1a of the env's positions and velocities.
uint64_t StateFingerprint(const Env& env, const mjModel* m) {
  const mjData* d = env.data();
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const double* x, int n) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(x);
    for (size_t i = 0; i < sizeof(double) * n; ++i) {
      h ^= bytes[i];
      h *= 1099511628211ull;
    }
  };
  mix(d->qpos, m->nq);
  mix(d->qvel, m->nv);
  return h;
}

// Salts the robust cost's noise streams apart from the search's (same seed, stream and re-plan).
constexpr uint64_t kRobustNoiseSalt = 0x726f62757374ULL;  // "robust"

}  // namespace

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
      space_(MakeSoccerSearchSpace(layout_, config_)),
      anchors_(MakeLandingAnchors(*spec_, config_.cost().landing_from_stance_foot())) {
  settings_.samples = config_.samples();
  settings_.iterations = config_.iterations();
  settings_.elite_fraction = config_.elite_fraction();
  settings_.keep_elite_fraction = config_.keep_elite_fraction();
  settings_.min_sigma_fraction = config_.min_sigma_fraction();
  settings_.explore_fraction = config_.explore_fraction();
  settings_.converged_fraction = config_.converged_fraction();
  theta_.assign(layout_.dim(), 0.0);
  rescue_space_ = space_;
  if (config_.rescue().body()) {
    // The regular search keeps the body knots of its warm start.
    std::fill(space_.sigma.begin() + layout_.kick_dim(), space_.sigma.end(), 0.0);
  }
  for (int v = 0; v < rescue_space_.dim(); ++v) {
    rescue_space_.sigma[v] = std::min(rescue_space_.sigma[v] * config_.rescue().sigma_scale(),
                                      rescue_space_.upper[v] - rescue_space_.lower[v]);
  }
}

SoccerPlanner::RolloutResult SoccerPlanner::Rollout(JuggleEnv* env, const double* theta,
                                                    PlanClock clock,
                                                    std::vector<uint64_t>* trace, double bound,
                                                    const float* noise) {
  RolloutResult result;
  SoccerRolloutScorer scorer(config_.cost(), layout_.horizon, &anchors_);
  scorer.Begin(*env);
  float action[kNumActions];
  int node = env->node();
  int t = 0;
  int end = layout_.horizon;
  for (; t < end; ++t, ++clock.step) {
    SoccerPlanAction(*env, layout_, theta, clock, action);
    if (noise != nullptr) {
      const float* n = noise + size_t(t) * kNumActions;
      for (int i = 0; i < kNumActions; ++i) action[i] = std::clamp(action[i] + n[i], -1.0f, 1.0f);
    }
    const StepResult r = env->Step(action, walk_);
    if (trace != nullptr) trace->push_back(StateFingerprint(*env, spec_->model()));
    scorer.AfterStep(*env, action, r);
    if (r.outcome != Outcome::kRunning) {
      result.end = r.outcome;
      ++t;
      break;
    }
    if (config_.prune() && scorer.partial() >= bound) {
      ++t;
      result.first_kick = scorer.first_kick();
      result.steps = t;
      result.cost = scorer.partial();
      return result;
    }
    if (config_.steps_after_kick() > 0 && scorer.kicks() == 1 && end == layout_.horizon) {
      end = std::min(end, t + 1 + config_.steps_after_kick());
    }
    // A horizon that would end with the ball still on the foot runs on to its release (a
    // few steps) so that the kick is scored.
    if (t + 1 == end && end >= layout_.horizon && end < layout_.horizon + kReleaseSteps &&
        scorer.kick_in_contact(*env) && (config_.run_on_every_kick() || scorer.kicks() == 0)) {
      ++end;
    }
    if (env->node() != node) {
      node = env->node();
      if (spec_->graph().node(node).stage == config::DOWN) ++clock.cycle;
    }
  }
  result.first_kick = scorer.first_kick();
  result.steps = t;
  result.cost = scorer.Finish(*env);
  result.missed = scorer.missed();
  return result;
}

absl::StatusOr<double> SoccerPlanner::Evaluate(const JuggleEnv& env,
                                               const std::vector<double>& theta,
                                               KickOutcome* kick, int draw) {
  JUGGLE_CHECK(static_cast<int>(theta.size()) == layout_.dim(), "plan of the wrong size");
  JUGGLE_CHECK(draw == 0 || (draw <= config_.robust().draws() && !robust_noise_.empty()),
               "no such robust draw (PlannerConfig.robust, after a re-plan)");
  const std::unique_ptr<EnvSnapshot> snapshot = env.Snapshot();
  double cost = 0;
  absl::Status s = pool_->Run(*snapshot, 1, [&](int, Env* copy) {
    const PlanClock clock{env.steps() - KnotAtOrBefore(layout_, env.steps()), 0};
    const RolloutResult r =
        Rollout(static_cast<JuggleEnv*>(copy), theta.data(), clock, nullptr,
                std::numeric_limits<double>::infinity(), draw > 0 ? RobustNoise(draw) : nullptr);
    cost = r.cost;
    if (kick != nullptr) *kick = r.first_kick;
  });
  if (!s.ok()) return s;
  return cost;
}

absl::StatusOr<std::vector<SoccerPlanner::RolloutResult>> SoccerPlanner::RolloutBatch(
    const EnvSnapshot& snapshot, PlanClock clock, const std::vector<double>& candidates, int n,
    double bound) {
  const int dim = layout_.dim();
  const int draws = config_.robust().draws();
  // Job j: candidate j / (1 + draws), draw j % (1 + draws) (0: noiseless). Pruning only
  // without draws: a bound on the mean does not bound one rollout.
  const int per = 1 + draws;
  const double rollout_bound = draws == 0 ? bound : std::numeric_limits<double>::infinity();
  std::vector<RolloutResult> all(size_t(n) * per);
  RETURN_IF_ERROR(pool_->Run(snapshot, n * per, [&](int j, Env* copy) {
    const int draw = j % per;
    all[j] = Rollout(static_cast<JuggleEnv*>(copy), candidates.data() + (j / per) * dim, clock,
                     nullptr, rollout_bound, draw > 0 ? RobustNoise(draw) : nullptr);
  }));
  for (const RolloutResult& r : all) totals_.rollout_steps += r.steps;
  if (per == 1) return all;
  std::vector<RolloutResult> results(n);
  for (int i = 0; i < n; ++i) {
    results[i] = all[size_t(i) * per];
    double sum = 0;
    for (int d = 0; d < per; ++d) sum += all[size_t(i) * per + d].cost;
    results[i].cost = sum / per;
  }
  totals_.rollouts += int64_t(n) * draws;
  return results;
}

absl::Status SoccerPlanner::Refine(const EnvSnapshot& snapshot, PlanClock clock, int set,
                                   const std::vector<double>& warm, std::vector<double>* theta,
                                   double* cost) {
  const int dim = layout_.dim();
  const int first = layout_.kick(set);
  const config::PlannerCost& w = config_.cost();
  // Finite-difference steps: 2 ms of timing, 0.01 rad of placement.
  const double h[kKickVariables] = {0.002, 0.01, 0.01, 0.01, 0.01};
  auto residual = [&](const KickOutcome& k, double out[3]) {
    out[0] = k.timing / w.timing_scale_s();
    out[1] = k.dx / w.landing_scale();
    out[2] = k.dy / w.landing_scale();
  };
  for (int it = 0; it < config_.refine_iterations(); ++it) {
    std::vector<double> batch;
    for (int j = -1; j < kKickVariables; ++j) {
      batch.insert(batch.end(), theta->begin(), theta->end());
      if (j >= 0) batch[batch.size() - dim + first + j] += h[j];
    }
    ASSIGN_OR_RETURN(std::vector<RolloutResult> probes,
                     RolloutBatch(snapshot, clock, batch, kKickVariables + 1));
    totals_.rollouts += kKickVariables + 1;
    if (!probes[0].first_kick.valid) return absl::OkStatus();
    double f[3], J[3][kKickVariables];
    residual(probes[0].first_kick, f);
    for (int j = 0; j < kKickVariables; ++j) {
      if (!probes[j + 1].first_kick.valid) return absl::OkStatus();
      double fj[3];
      residual(probes[j + 1].first_kick, fj);
      for (int r = 0; r < 3; ++r) J[r][j] = (fj[r] - f[r]) / h[j];
    }
    // Levenberg-Marquardt: (JᵀJ + λ·diag(JᵀJ) + μI) Δ = −Jᵀf.
    double A[kKickVariables * kKickVariables], b[kKickVariables];
    for (int i = 0; i < kKickVariables; ++i) {
      b[i] = 0;
      for (int r = 0; r < 3; ++r) b[i] -= J[r][i] * f[r];
      for (int j = 0; j < kKickVariables; ++j) {
        double s = 0;
        for (int r = 0; r < 3; ++r) s += J[r][i] * J[r][j];
        A[i * kKickVariables + j] = s;
      }
    }
    // The kick prior (PlannerCost.kick_prior) as residual rows √(prior / kick)·v / spread_v.
    const double prior = w.kick() > 0 ? w.kick_prior() / w.kick() : 0;
    for (int i = 0; i < kKickVariables; ++i) {
      const double s = space_.sigma[first + i];
      if (prior > 0 && s > 0) {
        A[i * kKickVariables + i] += prior / (s * s);
        b[i] -= prior * (*theta)[first + i] / (s * s);
      }
    }
    for (int i = 0; i < kKickVariables; ++i) {
      A[i * kKickVariables + i] += 0.1 * A[i * kKickVariables + i] + 1e-3;
    }
    double delta[kKickVariables];
    mju_copy(delta, b, kKickVariables);
    if (mju_cholFactor(A, kKickVariables, 1e-12) < kKickVariables) return absl::OkStatus();
    mju_cholSolve(delta, A, b, kKickVariables);
    batch.clear();
    for (const double alpha : {1.0, 0.5, 0.25}) {
      batch.insert(batch.end(), theta->begin(), theta->end());
      double* x = batch.data() + batch.size() - dim;
      for (int j = 0; j < kKickVariables; ++j) {
        x[first + j] =
            std::clamp(x[first + j] + alpha * delta[j], space_.lower[first + j], space_.upper[first + j]);
      }
    }
    ASSIGN_OR_RETURN(std::vector<RolloutResult> steps, RolloutBatch(snapshot, clock, batch, 3));
    totals_.rollouts += 3;
    int best = -1;
    for (int k = 0; k < 3; ++k) {
      steps[k].cost += Regularization(batch.data() + k * dim, warm);
      if (steps[k].cost < *cost && (best < 0 || steps[k].cost < steps[best].cost)) best = k;
    }
    if (best < 0) return absl::OkStatus();
    std::copy_n(batch.begin() + best * dim, dim, theta->begin());
    *cost = steps[best].cost;
  }
  return absl::OkStatus();
}

void SoccerPlanner::DrawRobustNoise(uint64_t draw_index) {
  const config::RobustCost& robust = config_.robust();
  if (robust.draws() == 0) return;
  robust_noise_.assign(size_t(robust.draws()) * robust_rows() * kNumActions, 0.0f);
  Rng rng = Rng::ForStream(config_.seed() ^ kRobustNoiseSalt, stream_, draw_index);
  for (int d = 1; d <= robust.draws(); ++d) {
    float* noise = robust_noise_.data() + size_t(d - 1) * robust_rows() * kNumActions;
    for (int t = 0; t < robust_rows(); ++t) {
      float* row = noise + size_t(t) * kNumActions;
      if (t % robust.hold_steps() == 0) {
        for (int i = 0; i < kNumActions; ++i) row[i] = float(robust.action_noise() * rng.Normal());
      } else {
        std::copy_n(row - kNumActions, kNumActions, row);
      }
    }
  }
}

double SoccerPlanner::Regularization(const double* theta, const std::vector<double>& warm) const {
  const double consistency = has_plan_ ? config_.cost().kick_consistency() : 0;
  const double prior = config_.cost().kick_prior();
  if (consistency <= 0 && prior <= 0) return 0;
  double sum = 0;
  for (int v = 0; v < layout_.kick_dim(); ++v) {
    if (space_.sigma[v] <= 0) continue;
    sum += consistency * std::pow((theta[v] - warm[v]) / space_.sigma[v], 2) +
           prior * std::pow(theta[v] / space_.sigma[v], 2);
  }
  return sum;
}

absl::Status SoccerPlanner::Replan(const JuggleEnv& env) {
  const int knot0 = KnotAtOrBefore(layout_, env.steps());
  const int moved = layout_.knot_steps > 0 ? (knot0 - knot0_step_) / layout_.knot_steps : 0;
  // The previous plan shifted to now (the consistency term's reference and a frozen kick's
  // value), and the search's start: the same, or the configured swing (cold_start).
  const std::vector<double> shifted = has_plan_
                                          ? ShiftSoccerPlan(layout_, theta_, moved, cycle_ - origin_cycle_)
                                          : std::vector<double>(layout_.dim(), 0.0);
  const std::vector<double> start =
      config_.cold_start() ? std::vector<double>(layout_.dim(), 0.0) : shifted;
  const PlanClock clock{env.steps() - knot0, 0};
  const std::unique_ptr<EnvSnapshot> snapshot = env.Snapshot();
  // A cold start draws from the state's step, so the same state gets the same answer whatever
  // came before it; otherwise from the re-plan's count.
  const uint64_t draw_index = config_.cold_start() ? static_cast<uint64_t>(env.steps())
                                                   : static_cast<uint64_t>(replan_count_);
  Rng rng = Rng::ForStream(config_.seed(), stream_, draw_index);
  DrawRobustNoise(draw_index);
  ++replan_count_;
  absl::Status status;
  const BatchCost cost = [&](const std::vector<double>& candidates, int n, double bound,
                             std::vector<double>* costs) {
    absl::StatusOr<std::vector<RolloutResult>> r =
        RolloutBatch(*snapshot, clock, candidates, n, bound);
    if (!r.ok()) {
      status = r.status();
      std::fill(costs->begin(), costs->end(), 0.0);
      return;
    }
    for (int i = 0; i < n; ++i) {
      (*costs)[i] = (*r)[i].cost + Regularization(&candidates[size_t(i) * layout_.dim()], shifted);
    }
  };
  // Seeds: the shifted plan, and the same with the nominal kick (a carried kick that no longer
  // fits is then one candidate away from the configured swing).
  std::vector<std::vector<double>> seeds = {start};
  if (layout_.kick_sets > 0) {
    seeds.push_back(start);
    std::fill(seeds.back().begin(), seeds.back().begin() + layout_.kick_dim(), 0.0);
  }
  // After the current cycle's release its kick set is held where it is.
  SearchSpace space = space_;
  const bool released = env.state().kick_touched && !env.state().touched_this_step;
  if (config_.kick().freeze_after_release() && released && layout_.kick_sets > 0) {
    for (int v = 0; v < kKickVariables; ++v) {
      space.lower[v] = space.upper[v] = shifted[v];
      space.sigma[v] = 0;
    }
    for (std::vector<double>& seed : seeds) std::copy_n(shifted.begin(), kKickVariables, seed.begin());
  }
  CemResult result = MinimizeCem(space, settings_, seeds, &rng, cost);
  if (!status.ok()) return status;
  totals_.rollouts += result.evaluations;
  last_.rescued = false;
  const config::RescueSearch& rescue = config_.rescue();
  if (rescue.cost_above() > 0 && result.best_cost > rescue.cost_above()) {
    // In trouble: search again, wider, from the best plan found (its incumbent), so the
    // answer is never worse than the regular search's.
    SearchSpace wide = rescue_space_;
    for (int v = 0; v < wide.dim(); ++v) {
      if (space.sigma[v] == 0 && space.lower[v] == space.upper[v]) {  // a frozen kick
        wide.lower[v] = wide.upper[v] = space.lower[v];
        wide.sigma[v] = 0;
      }
    }
    CemSettings settings = settings_;
    settings.samples = rescue.samples();
    settings.iterations = rescue.iterations();
    std::vector<std::vector<double>> rescue_seeds = {result.best};
    rescue_seeds.insert(rescue_seeds.end(), seeds.begin(), seeds.end());
    const double incumbent = result.incumbent_cost;
    CemResult second = MinimizeCem(wide, settings, rescue_seeds, &rng, cost);
    if (!status.ok()) return status;
    totals_.rollouts += second.evaluations;
    ++totals_.rescues;
    second.evaluations += result.evaluations;
    second.incumbent_cost = incumbent;
    result = std::move(second);
    last_.rescued = true;
  }
  if (config_.refine_iterations() > 0 && layout_.kick_sets > 0) {
    // The set of the next kick inside the horizon (not a frozen one).
    const int set = std::min(env.state().kick_touched ? 1 : 0, layout_.kick_sets - 1);
    if (!(set == 0 && released && config_.kick().freeze_after_release())) {
      RETURN_IF_ERROR(Refine(*snapshot, clock, set, shifted, &result.best, &result.best_cost));
    }
  }
  theta_ = result.best;
  has_plan_ = true;
  origin_step_ = env.steps();
  knot0_step_ = knot0;
  origin_cycle_ = cycle_;
  ++totals_.replans;
  last_.env_step = env.steps();
  last_.incumbent_cost = result.incumbent_cost;
  last_.best_cost = result.best_cost;
  last_.evaluations = result.evaluations;
  // The chosen plan's prediction, for reports (one more rollout).
  RolloutResult chosen;
  predicted_.clear();
  status = pool_->Run(*snapshot, 1, [&](int, Env* copy) {
    chosen = Rollout(static_cast<JuggleEnv*>(copy), theta_.data(), clock, &predicted_);
  });
  ++totals_.rollouts;
  totals_.rollout_steps += chosen.steps;
  last_.predicted_kick = chosen.first_kick;
  last_.kick.assign(theta_.begin(), theta_.begin() + std::min(kKickVariables, layout_.kick_dim()));
  last_.predicted_end = chosen.end;
  last_.predicted_end_step = env.steps() + chosen.steps;
  last_.predicts_failure = chosen.end != Outcome::kRunning && chosen.end != Outcome::kTimeLimit;
  last_.predicts_miss = chosen.missed;
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
  if (has_plan_) {
    // The state the plan predicted for this step.
    const int k = env.steps() - origin_step_ - 1;
    if (k >= 0 && k < static_cast<int>(predicted_.size())) {
      ++totals_.prediction_checks;
      if (predicted_[k] != StateFingerprint(env, spec_->model())) ++totals_.prediction_mismatches;
    }
  }
  const bool follow = config_.warm_start_from_executed() && layout_.kick_sets > 0;
  if (follow && has_plan_) FollowExecutedAction(env);
  const bool due = config_.replan_at_cycle_start()
                       ? cycle_ != origin_cycle_
                       : env.steps() - origin_step_ >= config_.replan_every();
  if (!has_plan_ || due) {
    if (absl::Status s = Replan(env); !s.ok()) return s;
  }
  PlanClock clock{env.steps() - knot0_step_, cycle_ - origin_cycle_};
  SoccerPlanAction(env, layout_, theta_.data(), clock, action);
  if (follow) RecordActionMap(env, clock, action);
  return absl::OkStatus();
}

void SoccerPlanner::RecordActionMap(const JuggleEnv& env, PlanClock clock, const float* action) {
  ActionMap& m = action_map_;
  m.valid = true;
  m.step = env.steps();
  m.cycle = cycle_;
  m.set = std::clamp(clock.cycle, 0, layout_.kick_sets - 1);
  std::copy_n(action, kNumActions, m.action);
  // Finite differences: 2 ms of timing, 0.01 rad of placement (as Refine).
  const double h[kKickVariables] = {0.002, 0.01, 0.01, 0.01, 0.01};
  std::vector<double> probe = theta_;
  float moved[kNumActions];
  for (int j = 0; j < kKickVariables; ++j) {
    double& x = probe[layout_.kick(m.set) + j];
    const double x0 = x;
    x = x0 + h[j];
    SoccerPlanAction(env, layout_, probe.data(), clock, moved);
    x = x0;
    for (int a = 0; a < kNumActions; ++a) m.jacobian[a][j] = (moved[a] - action[a]) / h[j];
  }
}

void SoccerPlanner::FollowExecutedAction(const JuggleEnv& env) {
  const ActionMap& m = action_map_;
  if (!m.valid || m.step != env.steps() - 1 || m.cycle != cycle_) return;
  const float* applied = env.state().previous_action.data();
  // Ridge least squares in units of the search spreads: (SJᵀJS + λI) δ = SJᵀr, Δ = Sδ, over
  // the rows where neither action was clamped.
  const int first = layout_.kick(m.set);
  double S[kKickVariables];
  for (int j = 0; j < kKickVariables; ++j) S[j] = space_.sigma[first + j];
  double A[kKickVariables * kKickVariables] = {0}, b[kKickVariables] = {0};
  for (int a = 0; a < kNumActions; ++a) {
    if (std::abs(m.action[a]) >= 1 || std::abs(applied[a]) >= 1) continue;
    const double r = static_cast<double>(applied[a]) - m.action[a];
    for (int i = 0; i < kKickVariables; ++i) {
      const double ji = m.jacobian[a][i] * S[i];
      b[i] += ji * r;
      for (int j = 0; j < kKickVariables; ++j) A[i * kKickVariables + j] += ji * m.jacobian[a][j] * S[j];
    }
  }
  double largest = 0;
  for (int i = 0; i < kKickVariables; ++i) largest = std::max(largest, A[i * kKickVariables + i]);
  if (largest <= 0) return;  // the kick does not act here (outside its swing)
  for (int i = 0; i < kKickVariables; ++i) A[i * kKickVariables + i] += 1e-2 * largest + 1e-9;
  if (mju_cholFactor(A, kKickVariables, 0) < kKickVariables) return;
  double delta[kKickVariables];
  mju_cholSolve(delta, A, b, kKickVariables);
  for (int j = 0; j < kKickVariables; ++j) {
    double& x = theta_[first + j];
    x = std::clamp(x + S[j] * delta[j], space_.lower[first + j], space_.upper[first + j]);
  }
}

}  // namespace juggle::planner
