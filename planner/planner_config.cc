#include "planner/planner_config.h"

#include <optional>
#include <utility>

#include "absl/strings/str_cat.h"
#include "envs/registry.h"
#include "planner/tasks.h"

namespace juggle::planner {
namespace {

// The name of the task block `p` sets ("" when none).
std::string TaskBlockName(const config::PlannerConfig& p) {
  const google::protobuf::OneofDescriptor* task = p.GetDescriptor()->FindOneofByName("task");
  const google::protobuf::FieldDescriptor* set =
      p.GetReflection()->GetOneofFieldDescriptor(p, task);
  return set == nullptr ? "" : set->name();
}

}  // namespace

std::optional<FieldPath> BodyKnotRequest(const config::PlannerConfig& p) {
  if (p.has_body_knot_steps() && p.body_knot_steps() > 0) return FieldPath{{"body_knot_steps"}};
  if (p.body_actions_size() > 0) return FieldPath{{"body_actions"}};
  if (p.rescue().body()) return FieldPath{{"rescue"}, {"body"}};
  return std::nullopt;
}

absl::Status ValidatePlannerConfig(const LoadedConfig& config) {
  const config::PlannerConfig& p = config.run.planner();
  auto where = [&](const char* field) { return config.root.Where({{"planner"}, {field}}); };
  absl::StatusOr<const EnvFamily*> family = FamilyOf(config.run);
  if (!family.ok()) return family.status();
  const std::string family_name((*family)->name());
  absl::StatusOr<const PlanningTaskEntry*> task = PlanningTaskFor(family_name);
  if (!task.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(config.root.Where({{"planner"}}), ": ", task.status().message()));
  }
  const std::string block = TaskBlockName(p);
  if (!block.empty() && block != family_name) {
    return absl::InvalidArgumentError(
        absl::StrCat(where(block.c_str()), ": a planning task for ", block, ", but this run's "
                     "envs are of the ", family_name, " family"));
  }
  if (!(*task)->refines) {
    // Silently nothing would refine (PlanningTaskEntry::refines).
    const std::string no_refinement = absl::StrCat(
        ": the ", family_name, " planning task has no refinement (no residuals to take "
        "Levenberg-Marquardt steps on); set it to 0");
    if (p.refine_iterations() > 0) {
      return absl::InvalidArgumentError(absl::StrCat(where("refine_iterations"), no_refinement));
    }
    const std::pair<const char*, int> rescue_refinements[] = {
        {"refine_first", p.rescue().refine_first()}, {"refine_after", p.rescue().refine_after()}};
    for (const auto& [field, iterations] : rescue_refinements) {
      if (iterations > 0) {
        return absl::InvalidArgumentError(absl::StrCat(
            config.root.Where({{"planner"}, {"rescue"}, {field}}), no_refinement));
      }
    }
  }
  if (!(*task)->has_later_kicks && p.rescue().ignore_later_kicks()) {
    // Nothing would be left out, and every troubled re-plan would roll out once more.
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"ignore_later_kicks"}}), ": the ",
        family_name, " planning task's cost has no later kicks to leave out; remove it"));
  }
  if (std::optional<FieldPath> knots = BodyKnotRequest(p); knots && !(*task)->body_knots) {
    // Silently no knot would act (PlanningTaskEntry::body_knots).
    FieldPath path = {{"planner"}};
    path.insert(path.end(), knots->begin(), knots->end());
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where(path), ": the ", family_name, " planning task's plan has no whole-body "
        "knots; set planner.body_knot_steps to 0"));
  }
  if (p.rescue().body() && p.body_knot_steps() == 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"body"}}),
        ": the rescue searches the whole-body knots, but planner.body_knot_steps is 0 (none)"));
  }
  if (p.rescue().stop_below() > 0 && p.rescue().stop_below() > p.rescue().cost_above()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"stop_below"}}), ": a rescue that stops at ",
        p.rescue().stop_below(), " may stop still in trouble (planner.rescue.cost_above is ",
        p.rescue().cost_above(), "); set it at or below cost_above"));
  }
  if (p.rescue().half_fixed_above() > 0 &&
      !(p.rescue().half_fixed_above() < p.rescue().cost_above())) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"half_fixed_above"}}), ": ",
        p.rescue().half_fixed_above(), " is a bar below planner.rescue.cost_above (",
        p.rescue().cost_above(), ") after a troubled warm start; at or above it, it changes "
        "nothing: lower it or remove it"));
  }
  if (p.rescue().has_bayes()) {
    // The model picks every candidate: the cross-entropy method's sizes and decay mean nothing.
    const config::RescueSearch& r = p.rescue();
    const char* beside = r.has_samples()                     ? "samples"
                         : r.has_iterations()                ? "iterations"
                         : r.has_population_decay()          ? "population_decay"
                         : r.has_full_after_decay()          ? "full_after_decay"
                         : r.has_full_after_narrowed()       ? "full_after_narrowed"
                         : r.has_narrowed_samples()          ? "narrowed_samples"
                         : r.has_narrowed_iterations()       ? "narrowed_iterations"
                         : r.has_decay_half_fixed_only()     ? "decay_half_fixed_only"
                                                             : nullptr;
    if (beside != nullptr) {
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where({{"planner"}, {"rescue"}, {"bayes"}}),
          ": a model-based rescue chooses its own candidates, so planner.rescue.", beside,
          " does not apply; size it by bayes { evaluations initial batch } and remove ", beside));
    }
    if (r.bayes().evaluations() < r.bayes().initial() + 1) {
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where({{"planner"}, {"rescue"}, {"bayes"}, {"evaluations"}}), ": ",
          r.bayes().evaluations(), " rollouts leave none for the model after the troubled plan "
          "and ", r.bayes().initial(), " initial samples; raise it above initial"));
    }
  }
  if (p.rescue().pause_after_lost() > 0 && !(p.rescue().cost_above() > 0)) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"pause_after_lost"}}),
        ": a pause after a lost rescue needs a rescue (planner.rescue.cost_above is 0); set "
        "cost_above or remove it"));
  }
  if (p.rescue().narrowed_samples() > 0 && p.rescue().narrowed_samples() < 4) {
    // The cross-entropy search needs a few samples to fit its elites (RescueSearch.samples' 4).
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"narrowed_samples"}}), ": ",
        p.rescue().narrowed_samples(), " samples are too few for a search; use 0 (the rescue's "
        "samples) or at least 4"));
  }
  if (p.rescue().full_after_decay() && !(p.rescue().population_decay() > 1)) {
    // Without a decay the rescue is already the full one: it would run twice.
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"full_after_decay"}}),
        ": follows a decayed rescue with a full one, but planner.rescue.population_decay is ",
        p.rescue().population_decay(), " (no decay); set a decay above 1 or remove it"));
  }
  if (p.rescue().decay_half_fixed_only() &&
      !(p.rescue().population_decay() > 1 && p.rescue().half_fixed_above() > 0)) {
    // Without both there is no decay to confine, or no half-fixed rescue to confine it to.
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"decay_half_fixed_only"}}),
        ": confines the rescue's population decay to half-fixed re-plans, but ",
        p.rescue().population_decay() > 1 ? "planner.rescue.half_fixed_above is 0 (none)"
                                          : "planner.rescue.population_decay is 1 (no decay)",
        "; set it or remove this"));
  }
  if (p.prune_chunk() > 0 && (!p.prune() || p.robust().draws() > 0)) {
    // Groups only tighten a pruning bound; without one they only add waits.
    return absl::InvalidArgumentError(absl::StrCat(
        where("prune_chunk"), ": groups tighten the pruning bound, but ",
        p.prune() ? "planner.robust.draws > 0 turns pruning off" : "planner.prune is false",
        "; remove it or prune"));
  }
  if (p.search_prior_trust() && !p.policy_prior()) {
    return absl::InvalidArgumentError(absl::StrCat(
        where("search_prior_trust"), ": a trust in the learned proposal needs "
        "planner.policy_prior: true (without it there is no policy to trust; `juggle eval` "
        "sets it with --proposal=POLICY)"));
  }
  if (p.replan_every() > p.horizon_steps()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where("replan_every"), ": re-planning every ", p.replan_every(),
                     " steps leaves steps past the horizon of ", p.horizon_steps(),
                     " without a plan"));
  }
  if ((p.search_every() > 1) != (p.search_skip_below() > 0)) {
    const bool every = p.search_every() > 1;
    return absl::InvalidArgumentError(absl::StrCat(
        where(every ? "search_every" : "search_skip_below"), ": light re-plans need both ",
        "planner.search_every above 1 and planner.search_skip_below above 0 (",
        every ? "search_skip_below is 0: no warm start is healthy enough to skip a search"
              : "search_every is 1: every re-plan searches",
        ")"));
  }
  if ((p.light_from() > 0 || p.light_to() > 0) &&
      !(p.search_every() > 1 && p.light_from() < p.light_to())) {
    return absl::InvalidArgumentError(absl::StrCat(
        where(p.light_to() > 0 ? "light_to" : "light_from"), ": a window of light re-plans (",
        p.light_from(), " to ", p.light_to(), " after a rescue) needs planner.search_every above ",
        "1 and light_from below light_to"));
  }
  if (p.search_every() > 1 && p.cold_start()) {
    return absl::InvalidArgumentError(absl::StrCat(
        where("search_every"),
        ": light re-plans keep the previous plan, and "
        "planner.cold_start starts every re-plan from the configured swing; remove one"));
  }
  if (p.search_skip_below() > 0 && p.rescue().cost_above() > 0 &&
      p.search_skip_below() >= p.rescue().cost_above()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where("search_skip_below"), ": ", p.search_skip_below(),
                     " is not below planner.rescue.cost_above (", p.rescue().cost_above(),
                     "): a re-plan in trouble would keep its plan without a search"));
  }
  if (p.replan_every_max() > p.horizon_steps()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where("replan_every_max"), ": re-planning up to every ", p.replan_every_max(),
                     " steps leaves steps past the horizon of ", p.horizon_steps(),
                     " without a plan"));
  }
  return (*task)->validate(config);
}

absl::Status RequirePlannerBlock(const LoadedConfig& config) {
  if (config.run.has_planner()) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(
      config.config_path, ": has no planner block, and the planner's defaults match no documented "
      "result; use a planner config (configs/right_foot_planner.textproto, or see "
      "docs/planner.md) or add a `planner { ... }` block"));
}

absl::Status ApplyPlannerSettings(const std::string& text, LoadedConfig* config) {
  if (text.empty()) return absl::OkStatus();
  config::PlannerConfig changes;
  absl::StatusOr<SourceLocator> parsed = ParseTextMessage(text, "--planner-set", &changes);
  if (!parsed.ok()) return parsed.status();
  // planner.kick and planner.cost moved into the soccer task's block: the old place still works.
  // (The task blocks are a oneof: the soccer block is touched only for them, or it would clear
  // another task's settings, e.g. football { ... }.)
  if (changes.has_kick() || changes.has_cost()) {
    config::SoccerJugglePlanning* task = changes.mutable_soccer_juggle();
    if ((changes.has_kick() && task->has_kick()) || (changes.has_cost() && task->has_cost())) {
      const char* field = changes.has_kick() && task->has_kick() ? "kick" : "cost";
      return absl::InvalidArgumentError(absl::StrCat(
          parsed->Where({{field}}), ": set both here and in soccer_juggle { ", field,
          " { ... } }; it belongs in soccer_juggle (docs/planner.md)"));
    }
    if (changes.has_kick()) task->mutable_kick()->Swap(changes.mutable_kick());
    if (changes.has_cost()) task->mutable_cost()->Swap(changes.mutable_cost());
    changes.clear_kick();
    changes.clear_cost();
  }
  config->run.mutable_planner()->MergeFrom(changes);
  return absl::OkStatus();
}

}  // namespace juggle::planner
