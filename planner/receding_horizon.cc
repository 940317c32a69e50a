// The receding-horizon driver (planner/receding_horizon.h): scheduling, the warm start, the
// search and its rescue, the refinement, the prediction check. Everything about what a plan
// means and costs is the task's (planner/planning_task.h).
#include "planner/receding_horizon.h"

#include <algorithm>
#include <cmath>

#include "absl/cleanup/cleanup.h"
#include "common/check.h"
#include "common/status_macros.h"
#include "planner/bayes_search.h"

namespace juggle::planner {
namespace {

// Salts the robust cost's noise streams apart from the search's (same seed, stream and re-plan).
constexpr uint64_t kRobustNoiseSalt = 0x726f62757374ULL;  // "robust"

// The refinement and the action map work on blocks of at most this many variables.
constexpr int kMaxBlock = 16;

}  // namespace

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

void PlannerTotals::Add(const PlannerTotals& other) {
  replans += other.replans;
  rollouts += other.rollouts;
  rollout_steps += other.rollout_steps;
  rescues += other.rescues;
  rescue_rollout_steps += other.rescue_rollout_steps;
  light_replans += other.light_replans;
  refined_out_of_trouble += other.refined_out_of_trouble;
  full_after_decay += other.full_after_decay;
  full_after_narrowed += other.full_after_narrowed;
  half_fixed_rescues += other.half_fixed_rescues;
  rescues_paused += other.rescues_paused;
  proposal_tried += other.proposal_tried;
  proposal_chosen += other.proposal_chosen;
  proposal_weight_sum += other.proposal_weight_sum;
  prediction_checks += other.prediction_checks;
  prediction_mismatches += other.prediction_mismatches;
  exact_rollouts += other.exact_rollouts;
  exact_rollout_steps += other.exact_rollout_steps;
  model_checks += other.model_checks;
  model_disagreements += other.model_disagreements;
  model_overrides += other.model_overrides;
  model_cost_gap_sum += other.model_cost_gap_sum;
}

struct RecedingHorizonPlanner::ReplanState {
  std::unique_ptr<EnvSnapshot> snapshot;
  PlanClock clock;
  int knot0 = 0;
  std::vector<double> shifted;  // the previous plan shifted to now (zero without one)
  std::vector<std::vector<double>> seeds;
  int proposal_seed = -1;       // index of the proposal alone in `seeds` (-1: not tried)
  SearchSpace space;            // the task's, restricted at this state
  Rng rng{0};
};

RecedingHorizonPlanner::RecedingHorizonPlanner(std::shared_ptr<const PlanningTask> task,
                                               const config::PlannerConfig& config,
                                               RolloutPool* pool, uint64_t stream,
                                               const ActionPrior* prior, RolloutPool* exact_pool)
    : task_(std::move(task)),
      config_(config),
      pool_(pool),
      exact_pool_(exact_pool),
      stream_(stream),
      prior_(prior),
      act_dim_(pool->spec().act_dim()),
      walk_(&pool->spec().graph()) {
  JUGGLE_CHECK(task_->family() == pool->spec().family(), "a task of another family than the pool");
  settings_.samples = config_.samples();
  settings_.iterations = config_.iterations();
  settings_.elite_fraction = config_.elite_fraction();
  settings_.keep_elite_fraction = config_.keep_elite_fraction();
  settings_.min_sigma_fraction = config_.min_sigma_fraction();
  settings_.explore_fraction = config_.explore_fraction();
  settings_.converged_fraction = config_.converged_fraction();
  settings_.population_decay = config_.population_decay();
  settings_.prune_chunk = config_.prune() ? config_.prune_chunk() : 0;
  theta_.assign(task_->dim(), 0.0);
  interval_ = config_.replan_every();
}

RecedingHorizonPlanner::RolloutResult RecedingHorizonPlanner::Rollout(
    Env* env, const double* theta, const RolloutOptions& o) const {
  RolloutResult result;
  const SharedPrefix* prefix = o.prefix;
  const std::unique_ptr<RolloutScorer> scorer =
      prefix != nullptr ? prefix->scorer->Clone() : task_->NewScorer();
  if (prefix == nullptr) scorer->Begin(*env);
  // PlanningModel.exact_within_m: the state moves to the executed model's twin near a contact
  // and back to the planning model away from it.
  const double exact_within = config_.planning_model().exact_within_m();
  Env* const planning_env = env;
  Env* const exact_env = exact_within > 0 ? pool_->TwinOf(env) : nullptr;
  auto switch_to = [&](Env* target) {
    const std::unique_ptr<EnvSnapshot> state = env->Snapshot();
    const absl::Status moved = target->Restore(*state);
    JUGGLE_CHECK(moved.ok(), "a twin env refused its pool env's state");
    env = target;
  };
  std::vector<float> action(act_dim_);
  std::vector<double> prior(prior_ != nullptr ? act_dim_ : 0);
  PlanClock clock = prefix != nullptr ? prefix->clock : o.clock;
  const int horizon = task_->horizon();
  int node = prefix != nullptr ? prefix->node : env->node();
  int t = prefix != nullptr ? prefix->steps : 0;
  int end = horizon;
  if (prefix != nullptr) {
    result.shared_steps = prefix->steps;
    if (o.trace != nullptr) {
      const size_t n = std::min(prefix->trace.size(), size_t(std::max(o.trace_steps, 0)));
      o.trace->insert(o.trace->end(), prefix->trace.begin(), prefix->trace.begin() + n);
    }
  }
  for (; t < end; ++t, ++clock.step) {
    if (exact_env != nullptr) {
      const bool near = task_->ContactClearance(*env) < exact_within;
      if (near && env == planning_env) switch_to(exact_env);
      if (!near && env == exact_env) switch_to(planning_env);
      if (env == exact_env) ++result.exact_steps;
    }
    if (prior_ != nullptr) prior_->Write(*env, prior.data());
    task_->Action(*env, theta, clock, prior_ != nullptr ? prior.data() : nullptr, action.data());
    if (o.noise != nullptr) {
      const float* n = o.noise + size_t(t) * act_dim_;
      for (int i = 0; i < act_dim_; ++i) action[i] = std::clamp(action[i] + n[i], -1.0f, 1.0f);
    }
    const StepResult r = env->Step(action.data(), walk_);
    if (o.trace != nullptr && static_cast<int>(o.trace->size()) < o.trace_steps) {
      o.trace->push_back(StateFingerprint(*env, pool_->spec().model()));
    }
    scorer->AfterStep(*env, action.data(), r);
    if (r.outcome != Outcome::kRunning) {
      result.end = r.outcome;
      ++t;
      break;
    }
    if (config_.prune() && scorer->partial() >= o.bound) {
      result.first_outcome = scorer->first_outcome();
      result.steps = t + 1;
      result.cost = scorer->partial();
      result.later = scorer->later_cost();
      result.pruned = true;
      return result;
    }
    // A horizon the task wants to run on (e.g. to a kick's release) gets one more step at a time.
    if (t + 1 == end && end < horizon + task_->max_run_on_steps() && scorer->RunsOn(*env)) ++end;
    if (env->node() != node) {
      node = env->node();
      if (task_->StartsCycle(*env, node)) ++clock.cycle;
    }
  }
  result.first_outcome = scorer->first_outcome();
  result.steps = t;
  result.cost = scorer->Finish(*env);
  result.later = scorer->later_cost();
  result.missed = scorer->predicts_miss();
  if (o.terms) result.terms = scorer->terms();
  return result;
}

absl::StatusOr<double> RecedingHorizonPlanner::Evaluate(const Env& env,
                                                        const std::vector<double>& theta,
                                                        std::vector<double>* outcome, int draw) {
  JUGGLE_CHECK(static_cast<int>(theta.size()) == task_->dim(), "plan of the wrong size");
  JUGGLE_CHECK(draw == 0 || (draw <= config_.robust().draws() && !robust_noise_.empty()),
               "no such robust draw (PlannerConfig.robust, after a re-plan)");
  const std::unique_ptr<EnvSnapshot> snapshot = env.Snapshot();
  RolloutOptions options;
  options.clock = {env.steps() - task_->KnotAtOrBefore(env.steps()), 0};
  options.noise = draw > 0 ? RobustNoise(draw) : nullptr;
  RolloutResult r;
  RETURN_IF_ERROR(pool_->Run(*snapshot, 1, [&](int, Env* copy) {
    r = Rollout(copy, theta.data(), options);
  }));
  if (outcome != nullptr) *outcome = r.first_outcome;
  return r.cost;
}

const RecedingHorizonPlanner::SharedPrefix* RecedingHorizonPlanner::PrefixFor(
    const EnvSnapshot& snapshot, PlanClock clock, const double* theta, double bound) {
  if (!config_.share_prefix() || config_.robust().draws() > 0 ||
      config_.planning_model().exact_within_m() > 0) {
    return nullptr;
  }
  if (prefix_ == nullptr) {
    prefix_ = std::make_shared<SharedPrefix>();
    SharedPrefix& p = *prefix_;
    std::unique_ptr<RolloutScorer> scorer = task_->NewScorer();
    if (scorer->Clone() == nullptr) return nullptr;
    const absl::Status run = pool_->Run(snapshot, 1, [&](int, Env* env) {
      // The steps Rollout would take while no variable acts, stopping before the horizon's last
      // step (where a rollout may run on) and abandoned if the episode ends inside them.
      scorer->Begin(*env);
      std::vector<float> action(act_dim_);
      std::vector<double> prior(prior_ != nullptr ? act_dim_ : 0);
      PlanClock c = clock;
      int node = env->node();
      int t = 0;
      for (; t + 1 < task_->horizon() && !task_->PlanActs(*env, theta, c); ++t, ++c.step) {
        if (prior_ != nullptr) prior_->Write(*env, prior.data());
        task_->Action(*env, theta, c, prior_ != nullptr ? prior.data() : nullptr, action.data());
        const StepResult r = env->Step(action.data(), walk_);
        p.trace.push_back(StateFingerprint(*env, pool_->spec().model()));
        scorer->AfterStep(*env, action.data(), r);
        p.max_partial = std::max(p.max_partial, scorer->partial());
        if (r.outcome != Outcome::kRunning) {
          t = 0;
          break;
        }
        if (env->node() != node) {
          node = env->node();
          if (task_->StartsCycle(*env, node)) ++c.cycle;
        }
      }
      totals_.rollout_steps += p.trace.size();
      if (t == 0) return;
      p.steps = t;
      p.clock = c;
      p.node = node;
      p.state = env->Snapshot();
      p.scorer = std::move(scorer);
    });
    JUGGLE_CHECK(run.ok(), "a re-plan's snapshot failed to restore");
  }
  if (prefix_->state == nullptr) return nullptr;
  // A rollout bounded below the prefix's cost would have stopped inside it.
  if (config_.prune() && prefix_->max_partial >= bound) return nullptr;
  return prefix_.get();
}

absl::StatusOr<std::vector<RecedingHorizonPlanner::RolloutResult>>
RecedingHorizonPlanner::RolloutBatch(const EnvSnapshot& snapshot, PlanClock clock,
                                     const std::vector<double>& candidates, int n, double bound) {
  const int dim = task_->dim();
  const int draws = config_.robust().draws();
  // Job j: candidate j / (1 + draws), draw j % (1 + draws) (0: noiseless). Pruning only
  // without draws: a bound on the mean does not bound one rollout.
  const int per = 1 + draws;
  RolloutOptions options;
  options.clock = clock;
  options.bound = draws == 0 ? bound : std::numeric_limits<double>::infinity();
  std::vector<RolloutResult> all(size_t(n) * per);
  options.prefix = PrefixFor(snapshot, clock, candidates.data(), options.bound);
  const EnvSnapshot& start = options.prefix != nullptr ? *options.prefix->state : snapshot;
  // The re-plan's own noiseless rollouts on the executed model are kept (SeenRollout); the
  // others (Evaluate's, a planning model's) are not read again.
  const bool keep = &snapshot == seen_from_ && per == 1 && exact_pool_ == nullptr;
  std::vector<std::vector<uint64_t>> traces(keep ? size_t(n) : 0);
  if (keep) options.terms = true;
  options.trace_steps = TracedSteps();
  // A candidate this re-plan already simulated to its end is read, not simulated again, where
  // nothing may be pruned (an infinite bound): its result is the one a rollout would give.
  // The callers count every candidate as a rollout; the ones read are taken off here.
  std::vector<int> simulated;  // the candidates that run
  simulated.reserve(size_t(n));
  for (int i = 0; i < n; ++i) {
    const double* x = candidates.data() + size_t(i) * dim;
    const SeenRollout* seen =
        keep && std::isinf(options.bound) ? Seen(std::vector<double>(x, x + dim)) : nullptr;
    if (seen == nullptr) {
      simulated.push_back(i);
    } else {
      all[size_t(i)] = seen->result;
      --totals_.rollouts;
    }
  }
  if (!simulated.empty()) {
    RETURN_IF_ERROR(
        pool_->Run(start, static_cast<int>(simulated.size()) * per, [&](int j, Env* copy) {
          const int i = simulated[size_t(j / per)];
          const int draw = j % per;
          RolloutOptions job = options;
          job.noise = draw > 0 ? RobustNoise(draw) : nullptr;
          if (keep) job.trace = &traces[size_t(i)];
          all[size_t(i) * per + draw] = Rollout(copy, candidates.data() + size_t(i) * dim, job);
        }));
  }
  for (const int i : simulated) {
    for (int d = 0; d < per; ++d) {
      const RolloutResult& r = all[size_t(i) * per + d];
      totals_.rollout_steps += r.steps - r.exact_steps - r.shared_steps;
      totals_.exact_rollout_steps += r.exact_steps;
    }
  }
  for (const int i : simulated) {
    if (!keep || all[size_t(i)].pruned) continue;
    const double* x = candidates.data() + size_t(i) * dim;
    seen_.push_back(
        {std::vector<double>(x, x + dim), all[size_t(i)], std::move(traces[size_t(i)])});
  }
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

absl::Status RecedingHorizonPlanner::ScoreBatch(const ReplanState& r,
                                                const std::vector<double>& candidates, int n,
                                                double bound, std::vector<double>* costs) {
  ASSIGN_OR_RETURN(std::vector<RolloutResult> results,
                   RolloutBatch(*r.snapshot, r.clock, candidates, n, bound));
  for (int i = 0; i < n; ++i) {
    (*costs)[i] = results[i].cost +
                  task_->PlanCost(&candidates[size_t(i) * task_->dim()], r.shifted, has_plan_);
    if (logged_rescue_ > 0) {
      rescue_log_->Rollout(logged_rescue_, &candidates[size_t(i) * task_->dim()], task_->dim(),
                           results[i].first_outcome, (*costs)[i]);
    }
  }
  return absl::OkStatus();
}

RecedingHorizonPlanner::ReplanState RecedingHorizonPlanner::WarmStart(const Env& env) {
  ReplanState r;
  prefix_ = nullptr;  // a new state: its prefix is computed on first use
  r.knot0 = task_->KnotAtOrBefore(env.steps());
  r.clock = {env.steps() - r.knot0, 0};
  r.snapshot = env.Snapshot();
  seen_.clear();
  seen_from_ = r.snapshot.get();
  // The previous plan shifted to now (the plan cost's reference and a held block's value), and
  // the search's start: the same, or zero (cold_start).
  r.shifted = has_plan_ ? task_->Shift(theta_, r.knot0 - knot0_step_, cycle_ - origin_cycle_)
                       : std::vector<double>(task_->dim(), 0.0);
  const std::vector<double> start =
      config_.cold_start() ? std::vector<double>(task_->dim(), 0.0) : r.shifted;
  r.seeds = task_->Seeds(start);
  // The learned proposal alone (no offsets on the prior) is one of the first candidates, so
  // the search can always fall back on the policy, and its wins measure the policy's share.
  // A seed that already is the proposal alone (e.g. the nominal-kick seed of a plan without
  // body knots) stands for it, so no candidate is simulated twice.
  if (prior_ != nullptr && prior_->proposes()) {
    std::vector<double> alone = task_->ProposalAlone();
    const auto same = std::find(r.seeds.begin(), r.seeds.end(), alone);
    if (same != r.seeds.end()) {
      r.proposal_seed = static_cast<int>(same - r.seeds.begin());
    } else if (settings_.samples > static_cast<int>(r.seeds.size())) {
      r.proposal_seed = static_cast<int>(r.seeds.size());
      r.seeds.push_back(std::move(alone));
    }
  }
  r.space = task_->space();
  task_->Restrict(env, r.shifted, &r.space, &r.seeds);
  // A cold start draws from the state's step, so the same state gets the same answer whatever
  // came before it; otherwise from the re-plan's count.
  const uint64_t draw_index = config_.cold_start() ? static_cast<uint64_t>(env.steps())
                                                   : static_cast<uint64_t>(replan_count_);
  r.rng = Rng::ForStream(config_.seed(), stream_, draw_index);
  DrawRobustNoise(draw_index);
  ++replan_count_;
  return r;
}

absl::StatusOr<CemResult> RecedingHorizonPlanner::Search(ReplanState& r) {
  const BatchCost cost = [&](const std::vector<double>& candidates, int n, double bound,
                             std::vector<double>* costs) {
    return ScoreBatch(r, candidates, n, bound, costs);
  };
  last_.light = false;
  const int after_rescue = since_rescue_ + 1;  // this re-plan's count after the last rescue
  const bool in_window = config_.light_to() == 0 || (after_rescue >= config_.light_from() &&
                                                     after_rescue < config_.light_to());
  if (has_plan_ && config_.search_every() > 1 && light_streak_ + 1 < config_.search_every() &&
      in_window) {
    // The warm start alone (its horizon extended); kept while it is healthy.
    CemSettings alone = settings_;
    alone.samples = 1;
    alone.iterations = 1;
    ASSIGN_OR_RETURN(CemResult kept, MinimizeCem(r.space, alone, r.seeds, &r.rng, cost));
    totals_.rollouts += kept.evaluations;
    if (kept.best_cost <= config_.search_skip_below()) {
      ++light_streak_;
      ++totals_.light_replans;
      last_.light = true;
      return kept;
    }
    // Not healthy: the search below reads the warm start's rollout (RolloutBatch).
  }
  light_streak_ = 0;
  ASSIGN_OR_RETURN(CemResult result, MinimizeCem(r.space, settings_, r.seeds, &r.rng, cost));
  totals_.rollouts += result.evaluations;
  return result;
}

absl::StatusOr<bool> RecedingHorizonPlanner::InTrouble(const ReplanState& r,
                                                      const CemResult& result, double above,
                                                      double* measure) {
  if (!(above > 0 && result.best_cost > above)) return false;
  if (measure != nullptr) *measure = result.best_cost;
  if (!config_.rescue().ignore_later_kicks()) return true;
  // Trouble that only later decisions make is left to the re-plans after the first one.
  RolloutResult best;
  if (const SeenRollout* seen = Seen(result.best); seen != nullptr) {
    best = seen->result;
  } else {
    RolloutOptions plain;
    plain.clock = r.clock;
    plain.prefix = PrefixFor(*r.snapshot, r.clock, result.best.data(), plain.bound);
    RETURN_IF_ERROR(
        pool_->Run(plain.prefix != nullptr ? *plain.prefix->state : *r.snapshot, 1,
                   [&](int, Env* copy) { best = Rollout(copy, result.best.data(), plain); }));
    ++totals_.rollouts;
    totals_.rollout_steps += best.steps - best.shared_steps;
  }
  if (measure != nullptr) *measure = best.cost - best.later;
  return best.cost - best.later > above;
}

absl::Status RecedingHorizonPlanner::Rescue(const Env& env, ReplanState& r, CemResult* result) {
  last_.rescued = false;
  last_.refined_out = false;
  const config::RescueSearch& rescue = config_.rescue();
  // The bar for trouble: cost_above, or the lower half_fixed_above after a troubled warm start.
  double above = rescue.cost_above();
  if (rescue.half_fixed_above() > 0 && result->incumbent_cost > rescue.cost_above()) {
    above = std::min(above, rescue.half_fixed_above());
  }
  double measure = 0;
  ASSIGN_OR_RETURN(const bool in_trouble, InTrouble(r, *result, above, &measure));
  if (!in_trouble) {
    troubled_ = 0;
    return absl::OkStatus();
  }
  if (++troubled_ < rescue.patience()) return absl::OkStatus();
  troubled_ = 0;
  if (rescue_pause_ > 0) {
    // A rescue just failed to avert the episode's end: not again yet.
    ++totals_.rescues_paused;
    return absl::OkStatus();
  }
  if (rescue.refine_first() > 0) {
    // A linear step on the next kick first; the wide search only if still in trouble.
    RETURN_IF_ERROR(RefineNextKick(env, r, rescue.refine_first(), result));
    if (result->best_cost <= above) {
      ++totals_.refined_out_of_trouble;
      last_.refined_out = true;
      return absl::OkStatus();
    }
  }
  // In trouble: search again, wider, from the best plan found (its incumbent), so the answer is
  // never worse than the regular search's. Variables the state holds stay held.
  SearchSpace wide = task_->RescueSpaceAt(env);
  for (int v = 0; v < wide.dim(); ++v) {
    if (r.space.sigma[v] == 0 && r.space.lower[v] == r.space.upper[v]) {
      wide.lower[v] = wide.upper[v] = r.space.lower[v];
      wide.sigma[v] = 0;
    }
  }
  CemSettings settings = settings_;
  settings.samples = rescue.samples();
  settings.iterations = rescue.iterations();
  settings.population_decay = rescue.population_decay();
  // Half-fixed: in trouble only by the lower bar (a plan near a good one).
  const bool half_fixed = measure <= rescue.cost_above();
  if (half_fixed) ++totals_.half_fixed_rescues;
  if (rescue.decay_half_fixed_only() && !half_fixed) settings.population_decay = 1;
  if (rescue.stop_below() > 0) settings.stop_below = rescue.stop_below();
  std::vector<std::vector<double>> seeds = {result->best};
  seeds.insert(seeds.end(), r.seeds.begin(), r.seeds.end());
  // A rescue that holds more (soccer's hold_in_rescue) shares another prefix, if any.
  const SearchSpace open_space = wide;
  const std::vector<std::vector<double>> open_seeds = seeds;
  CemSettings open_settings = settings;
  bool narrowed = task_->RestrictRescue(env, r.shifted, &wide, &seeds);
  if (narrowed) {
    prefix_ = nullptr;
    if (rescue.narrowed_samples() > 0) settings.samples = rescue.narrowed_samples();
    if (rescue.narrowed_iterations() > 0) settings.iterations = rescue.narrowed_iterations();
  }
  const BatchCost cost = [&](const std::vector<double>& candidates, int n, double bound,
                             std::vector<double>* costs) {
    return ScoreBatch(r, candidates, n, bound, costs);
  };
  if (rescue_log_ != nullptr) logged_rescue_ = rescue_log_->Begin(stream_, env, result->best_cost);
  absl::Cleanup stop_logging = [this] { logged_rescue_ = 0; };  // also when a search fails
  CemResult second;
  if (rescue.has_bayes()) {
    BayesSettings bayes;
    bayes.evaluations = std::max(rescue.bayes().evaluations(), static_cast<int>(seeds.size()));
    bayes.initial = rescue.bayes().initial();
    bayes.batch = rescue.bayes().batch();
    bayes.stop_below = settings.stop_below;
    bayes.answer_noise = rescue.bayes().answer_noise();
    ASSIGN_OR_RETURN(second, MinimizeBayes(wide, bayes, seeds, &r.rng, cost));
  } else {
    ASSIGN_OR_RETURN(second, MinimizeCem(wide, settings, seeds, &r.rng, cost));
  }
  totals_.rollouts += second.evaluations;
  if (rescue.full_after_decay() && settings.population_decay > 1) {
    ASSIGN_OR_RETURN(const bool still, InTrouble(r, second, above));
    if (still) {
      // The cheap search failed here: the full population, from its best.
      settings.population_decay = 1;
      seeds[0] = second.best;
      ASSIGN_OR_RETURN(CemResult full, MinimizeCem(wide, settings, seeds, &r.rng, cost));
      totals_.rollouts += full.evaluations;
      ++totals_.full_after_decay;
      full.evaluations += second.evaluations;  // its incumbent: never worse than the decayed
      second = std::move(full);
    }
  }
  if (narrowed && rescue.full_after_narrowed()) {
    ASSIGN_OR_RETURN(const bool still, InTrouble(r, second, above));
    if (still) {
      // The narrowed search failed here: the same search without the narrowing, from the
      // regular search's best plan; the better answer of the two.
      prefix_ = nullptr;
      // The decay the narrowed search ended with (1 after full_after_decay), as before.
      open_settings.population_decay = settings.population_decay;
      ASSIGN_OR_RETURN(CemResult open,
                       MinimizeCem(open_space, open_settings, open_seeds, &r.rng, cost));
      totals_.rollouts += open.evaluations;
      ++totals_.full_after_narrowed;
      open.evaluations += second.evaluations;
      if (open.best_cost < second.best_cost) {
        second = std::move(open);
        narrowed = false;
      } else {
        second.evaluations = open.evaluations;
        prefix_ = nullptr;  // the narrowed answer's prefix again
      }
    }
  }
  if (logged_rescue_ > 0) {
    rescue_log_->End(logged_rescue_, second.best_cost, second.evaluations);
  }
  std::move(stop_logging).Invoke();
  if (narrowed && second.best_cost >= result->best_cost) {
    // The narrowed rescue found nothing better than the regular plan: that plan stays, with
    // its own prefix.
    prefix_ = nullptr;
    second.best = result->best;
    second.best_cost = result->best_cost;
  }
  RETURN_IF_ERROR(RefineNextKick(env, r, rescue.refine_after(), &second));
  ++totals_.rescues;
  second.evaluations += result->evaluations;
  second.incumbent_cost = result->incumbent_cost;
  *result = std::move(second);
  last_.rescued = true;
  return absl::OkStatus();
}

absl::Status RecedingHorizonPlanner::RefineBest(const Env& env, ReplanState& r,
                                                CemResult* result) {
  if (last_.light) return absl::OkStatus();  // a kept plan is not refined either
  return RefineNextKick(env, r, config_.refine_iterations(), result);
}

absl::Status RecedingHorizonPlanner::RefineNextKick(const Env& env, const ReplanState& r,
                                                    int iterations, CemResult* result) {
  if (iterations == 0) return absl::OkStatus();
  const std::optional<VariableBlock> block = task_->RefineBlock(env);
  if (!block.has_value()) return absl::OkStatus();
  return Refine(*r.snapshot, r.clock, *block, r.shifted, iterations, &result->best,
                &result->best_cost);
}

absl::Status RecedingHorizonPlanner::Refine(const EnvSnapshot& snapshot, PlanClock clock,
                                            const VariableBlock& block,
                                            const std::vector<double>& warm, int iterations,
                                            std::vector<double>* theta, double* cost) {
  const int dim = task_->dim();
  const int k = block.size();
  const int m = task_->num_residuals();
  JUGGLE_CHECK(k <= kMaxBlock && m <= kMaxBlock, "a refinement block or residual too large");
  const SearchSpace& space = task_->space();
  const double* h = block.steps.data();
  for (int it = 0; it < iterations; ++it) {
    std::vector<double> batch;
    for (int j = -1; j < k; ++j) {
      batch.insert(batch.end(), theta->begin(), theta->end());
      if (j >= 0) batch[batch.size() - dim + block.first + j] += h[j];
    }
    ASSIGN_OR_RETURN(std::vector<RolloutResult> probes, RolloutBatch(snapshot, clock, batch, k + 1));
    totals_.rollouts += k + 1;
    double f[kMaxBlock], J[kMaxBlock][kMaxBlock];
    if (!task_->Residuals(probes[0].first_outcome, f)) return absl::OkStatus();
    for (int j = 0; j < k; ++j) {
      double fj[kMaxBlock];
      if (!task_->Residuals(probes[j + 1].first_outcome, fj)) return absl::OkStatus();
      for (int row = 0; row < m; ++row) J[row][j] = (fj[row] - f[row]) / h[j];
    }
    // Levenberg-Marquardt: (JᵀJ + λ·diag(JᵀJ) + μI) Δ = −Jᵀf.
    double A[kMaxBlock * kMaxBlock], b[kMaxBlock];
    for (int i = 0; i < k; ++i) {
      b[i] = 0;
      for (int row = 0; row < m; ++row) b[i] -= J[row][i] * f[row];
      for (int j = 0; j < k; ++j) {
        double s = 0;
        for (int row = 0; row < m; ++row) s += J[row][i] * J[row][j];
        A[i * k + j] = s;
      }
    }
    // The task's prior as residual rows √prior·v / spread_v.
    const double prior = task_->refine_prior_weight();
    for (int i = 0; i < k; ++i) {
      const double s = space.sigma[block.first + i];
      if (prior > 0 && s > 0) {
        A[i * k + i] += prior / (s * s);
        b[i] -= prior * (*theta)[block.first + i] / (s * s);
      }
    }
    for (int i = 0; i < k; ++i) A[i * k + i] += 0.1 * A[i * k + i] + 1e-3;
    double delta[kMaxBlock];
    mju_copy(delta, b, k);
    if (mju_cholFactor(A, k, 1e-12) < k) return absl::OkStatus();
    mju_cholSolve(delta, A, b, k);
    batch.clear();
    for (const double alpha : {1.0, 0.5, 0.25}) {
      batch.insert(batch.end(), theta->begin(), theta->end());
      double* x = batch.data() + batch.size() - dim;
      for (int j = 0; j < k; ++j) {
        const int v = block.first + j;
        x[v] = std::clamp(x[v] + alpha * delta[j], space.lower[v], space.upper[v]);
      }
    }
    ASSIGN_OR_RETURN(std::vector<RolloutResult> steps, RolloutBatch(snapshot, clock, batch, 3));
    totals_.rollouts += 3;
    int best = -1;
    for (int s = 0; s < 3; ++s) {
      steps[s].cost += task_->PlanCost(batch.data() + s * dim, warm, has_plan_);
      if (steps[s].cost < *cost && (best < 0 || steps[s].cost < steps[best].cost)) best = s;
    }
    if (best < 0) return absl::OkStatus();
    std::copy_n(batch.begin() + best * dim, dim, theta->begin());
    *cost = steps[best].cost;
  }
  return absl::OkStatus();
}

absl::Status RecedingHorizonPlanner::ChooseOnExact(const ReplanState& r, bool had_plan,
                                                   RolloutResult* chosen) {
  RolloutOptions plain;
  plain.clock = r.clock;
  RolloutResult coarse;
  RETURN_IF_ERROR(pool_->Run(*r.snapshot, 1, [&](int, Env* copy) {
    coarse = Rollout(copy, theta_.data(), plain);
  }));
  ++totals_.rollouts;
  totals_.rollout_steps += coarse.steps;
  // The choice and the warm start on the executed model, each with its prediction and terms.
  const bool check = config_.planning_model().check_on_exact() && had_plan;
  RolloutResult exact, warm;
  std::vector<uint64_t> exact_trace, warm_trace;
  RETURN_IF_ERROR(exact_pool_->Run(*r.snapshot, check ? 2 : 1, [&](int i, Env* copy) {
    RolloutOptions o = plain;
    o.terms = true;
    o.trace = i == 0 ? &exact_trace : &warm_trace;
    (i == 0 ? exact : warm) = Rollout(copy, (i == 0 ? theta_ : r.shifted).data(), o);
  }));
  totals_.exact_rollouts += check ? 2 : 1;
  totals_.exact_rollout_steps += exact.steps + (check ? warm.steps : 0);
  ++totals_.model_checks;
  totals_.model_cost_gap_sum += exact.cost - coarse.cost;
  auto fails = [](const RolloutResult& x) {
    return x.missed || (x.end != Outcome::kRunning && x.end != Outcome::kTimeLimit);
  };
  if (fails(coarse) != fails(exact)) ++totals_.model_disagreements;
  if (check && warm.cost + task_->PlanCost(r.shifted.data(), r.shifted, had_plan) <
                   exact.cost + task_->PlanCost(theta_.data(), r.shifted, had_plan)) {
    theta_ = r.shifted;
    ++totals_.model_overrides;
    *chosen = std::move(warm);
    predicted_ = std::move(warm_trace);
  } else {
    *chosen = std::move(exact);
    predicted_ = std::move(exact_trace);
  }
  return absl::OkStatus();
}

absl::Status RecedingHorizonPlanner::Commit(const Env& env, const ReplanState& r,
                                            const CemResult& result) {
  const bool had_plan = has_plan_;
  theta_ = result.best;
  if (r.proposal_seed >= 0) {
    ++totals_.proposal_tried;
    if (theta_ == r.seeds[size_t(r.proposal_seed)]) ++totals_.proposal_chosen;
    totals_.proposal_weight_sum += task_->PriorWeight(theta_.data());
  }
  // The chosen plan's prediction: the states the next steps must visit. With a planning model
  // it is the executed model's (ChooseOnExact); else one more rollout.
  RolloutResult chosen;
  predicted_.clear();
  absl::Status status;
  if (exact_pool_ != nullptr) {
    status = ChooseOnExact(r, had_plan, &chosen);
  } else if (const SeenRollout* seen = Seen(theta_); seen != nullptr) {
    chosen = seen->result;
    predicted_ = seen->trace;
  } else {
    RolloutOptions options;
    options.clock = r.clock;
    options.trace = &predicted_;
    options.trace_steps = TracedSteps();
    options.terms = true;
    options.prefix = PrefixFor(*r.snapshot, r.clock, theta_.data(), options.bound);
    status = pool_->Run(options.prefix != nullptr ? *options.prefix->state : *r.snapshot, 1,
                        [&](int, Env* copy) { chosen = Rollout(copy, theta_.data(), options); });
    ++totals_.rollouts;
    totals_.rollout_steps += chosen.steps - chosen.shared_steps;
  }
  seen_.clear();  // the re-plan is over: its snapshot goes
  seen_from_ = nullptr;
  has_plan_ = true;
  origin_step_ = env.steps();
  knot0_step_ = r.knot0;
  origin_cycle_ = cycle_;
  ++totals_.replans;
  last_.env_step = env.steps();
  last_.node = env.node();
  last_.incumbent_cost = result.incumbent_cost;
  last_.best_cost = result.best_cost;
  last_.evaluations = result.evaluations;
  last_.predicted_outcome = chosen.first_outcome;
  last_.terms = chosen.terms;
  last_.decision.assign(theta_.begin(), theta_.begin() + task_->decision_size());
  last_.predicted_end = chosen.end;
  last_.predicted_end_step = env.steps() + chosen.steps;
  last_.predicts_failure = chosen.end != Outcome::kRunning && chosen.end != Outcome::kTimeLimit;
  last_.predicts_miss = chosen.missed;
  if (last_.rescued && last_.predicts_failure) {
    rescue_pause_ = config_.rescue().pause_after_lost();
  } else if (rescue_pause_ > 0) {
    --rescue_pause_;
  }
  // The next re-plan: sooner when this one paid, later (up to replan_every_max) when not.
  if (config_.replan_every_max() > config_.replan_every()) {
    const double gain = result.incumbent_cost - result.best_cost;
    const bool paid = last_.rescued || gain >= config_.replan_gain() * std::abs(result.incumbent_cost);
    interval_ = paid ? config_.replan_every()
                     : std::min(2 * interval_, config_.replan_every_max());
  }
  return status;
}

int RecedingHorizonPlanner::TracedSteps() const {
  if (config_.replan_at_cycle_start()) return std::numeric_limits<int>::max();
  return std::max(config_.replan_every(), config_.replan_every_max());
}

const RecedingHorizonPlanner::SeenRollout* RecedingHorizonPlanner::Seen(
    const std::vector<double>& theta) const {
  for (const SeenRollout& s : seen_) {
    if (s.theta == theta) return &s;
  }
  return nullptr;
}

absl::Status RecedingHorizonPlanner::Replan(const Env& env) {
  ReplanState r = WarmStart(env);
  ASSIGN_OR_RETURN(CemResult result, Search(r));
  const int64_t steps_before_rescue = totals_.rollout_steps;
  RETURN_IF_ERROR(Rescue(env, r, &result));
  if (last_.rescued) totals_.rescue_rollout_steps += totals_.rollout_steps - steps_before_rescue;
  since_rescue_ = last_.rescued ? 0 : std::min(since_rescue_ + 1, kNoRescueYet);
  RETURN_IF_ERROR(RefineBest(env, r, &result));
  return Commit(env, r, result);
}

void RecedingHorizonPlanner::DrawRobustNoise(uint64_t draw_index) {
  const config::RobustCost& robust = config_.robust();
  if (robust.draws() == 0) return;
  robust_noise_.assign(size_t(robust.draws()) * robust_rows() * act_dim_, 0.0f);
  Rng rng = Rng::ForStream(config_.seed() ^ kRobustNoiseSalt, stream_, draw_index);
  for (int d = 1; d <= robust.draws(); ++d) {
    float* noise = robust_noise_.data() + size_t(d - 1) * robust_rows() * act_dim_;
    for (int t = 0; t < robust_rows(); ++t) {
      float* row = noise + size_t(t) * act_dim_;
      if (t % robust.hold_steps() == 0) {
        for (int i = 0; i < act_dim_; ++i) row[i] = float(robust.action_noise() * rng.Normal());
      } else {
        std::copy_n(row - act_dim_, act_dim_, row);
      }
    }
  }
}

void RecedingHorizonPlanner::TrackCycles(const Env& env) {
  if (env.steps() <= last_step_ || last_step_ < 0) {
    // A new episode.
    has_plan_ = false;
    cycle_ = 0;
    interval_ = config_.replan_every();
    troubled_ = 0;
    light_streak_ = 0;
    rescue_pause_ = 0;
    since_rescue_ = kNoRescueYet;
    last_node_ = env.node();
  } else if (env.node() != last_node_) {
    last_node_ = env.node();
    if (task_->StartsCycle(env, last_node_)) ++cycle_;
  }
  last_step_ = env.steps();
}

void RecedingHorizonPlanner::CheckPrediction(const Env& env) {
  if (!has_plan_) return;
  // The state the plan predicted for this step.
  const int k = env.steps() - origin_step_ - 1;
  if (k >= 0 && k < static_cast<int>(predicted_.size())) {
    ++totals_.prediction_checks;
    if (predicted_[k] != StateFingerprint(env, pool_->spec().model())) {
      ++totals_.prediction_mismatches;
    }
  }
}

absl::Status RecedingHorizonPlanner::Act(const Env& env, float* action) {
  TrackCycles(env);
  CheckPrediction(env);
  const bool follow = config_.warm_start_from_executed();
  if (follow && has_plan_) FollowExecutedAction(env);
  const bool due = config_.replan_at_cycle_start()
                       ? cycle_ != origin_cycle_
                       : env.steps() - origin_step_ >= interval_;
  if (!has_plan_ || due) RETURN_IF_ERROR(Replan(env));
  const PlanClock clock{env.steps() - knot0_step_, cycle_ - origin_cycle_};
  std::vector<double> prior(prior_ != nullptr ? act_dim_ : 0);
  if (prior_ != nullptr) prior_->Write(env, prior.data());
  task_->Action(env, theta_.data(), clock, prior_ != nullptr ? prior.data() : nullptr, action);
  if (follow) RecordActionMap(env, clock, action);
  return absl::OkStatus();
}

void RecedingHorizonPlanner::RecordActionMap(const Env& env, PlanClock clock,
                                             const float* action) {
  ActionMap& m = action_map_;
  const std::optional<VariableBlock> block = task_->ActingBlock(clock);
  m.valid = block.has_value();
  if (!m.valid) return;
  m.step = env.steps();
  m.cycle = cycle_;
  m.block = *block;
  m.action.assign(action, action + act_dim_);
  const int k = m.block.size();
  m.jacobian.assign(size_t(act_dim_) * k, 0.0);
  std::vector<double> prior(prior_ != nullptr ? act_dim_ : 0);
  if (prior_ != nullptr) prior_->Write(env, prior.data());
  // Finite differences of the plan's action in each variable of the block.
  std::vector<double> probe = theta_;
  std::vector<float> moved(act_dim_);
  for (int j = 0; j < k; ++j) {
    double& x = probe[m.block.first + j];
    const double x0 = x;
    x = x0 + m.block.steps[j];
    task_->Action(env, probe.data(), clock, prior_ != nullptr ? prior.data() : nullptr,
                  moved.data());
    x = x0;
    for (int a = 0; a < act_dim_; ++a) {
      m.jacobian[size_t(a) * k + j] = (moved[a] - action[a]) / m.block.steps[j];
    }
  }
}

void RecedingHorizonPlanner::FollowExecutedAction(const Env& env) {
  const ActionMap& m = action_map_;
  if (!m.valid || m.step != env.steps() - 1 || m.cycle != cycle_) return;
  const float* applied = task_->AppliedAction(env);
  if (applied == nullptr) return;
  // Ridge least squares in units of the search spreads: (SJᵀJS + λI) δ = SJᵀr, Δ = Sδ, over
  // the rows where neither action was clamped.
  const SearchSpace& space = task_->space();
  const int first = m.block.first;
  const int k = m.block.size();
  JUGGLE_CHECK(k <= kMaxBlock, "an acting block too large");
  double S[kMaxBlock];
  for (int j = 0; j < k; ++j) S[j] = space.sigma[first + j];
  double A[kMaxBlock * kMaxBlock] = {0}, b[kMaxBlock] = {0};
  for (int a = 0; a < act_dim_; ++a) {
    if (std::abs(m.action[a]) >= 1 || std::abs(applied[a]) >= 1) continue;
    const double r = static_cast<double>(applied[a]) - m.action[a];
    const double* row = m.jacobian.data() + size_t(a) * k;
    for (int i = 0; i < k; ++i) {
      const double ji = row[i] * S[i];
      b[i] += ji * r;
      for (int j = 0; j < k; ++j) A[i * k + j] += ji * row[j] * S[j];
    }
  }
  double largest = 0;
  for (int i = 0; i < k; ++i) largest = std::max(largest, A[i * k + i]);
  if (largest <= 0) return;  // the block does not act here
  for (int i = 0; i < k; ++i) A[i * k + i] += 1e-2 * largest + 1e-9;
  if (mju_cholFactor(A, k, 0) < k) return;
  double delta[kMaxBlock];
  mju_cholSolve(delta, A, b, k);
  for (int j = 0; j < k; ++j) {
    double& x = theta_[first + j];
    x = std::clamp(x + S[j] * delta[j], space.lower[first + j], space.upper[first + j]);
  }
}

}  // namespace juggle::planner
