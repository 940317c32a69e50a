#include "planner/planner_controller.h"

#include "absl/strings/str_cat.h"
#include "common/check.h"
#include "planner/soccer_plan.h"

namespace juggle::planner {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

absl::Status ApplyPlannerSettings(const std::string& text, LoadedConfig* config) {
  if (text.empty()) return absl::OkStatus();
  config::PlannerConfig changes;
  absl::StatusOr<SourceLocator> parsed = ParseTextMessage(text, "--planner-set", &changes);
  if (!parsed.ok()) return parsed.status();
  config->run.mutable_planner()->MergeFrom(changes);
  return absl::OkStatus();
}

absl::Status ValidatePlannerConfig(const LoadedConfig& config) {
  const config::PlannerConfig& p = config.run.planner();
  auto where = [&](const char* field) { return config.root.Where({{"planner"}, {field}}); };
  if (!config.run.has_soccer_juggle()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}}),
        ": the planner drives soccer_juggle envs; this config's family has no planner yet"));
  }
  const int episode = config.run.soccer_juggle().env().max_episode_steps();
  if (p.horizon_steps() > episode) {
    return absl::InvalidArgumentError(absl::StrCat(
        where("horizon_steps"), ": a horizon of ", p.horizon_steps(),
        " control steps is longer than the episode (soccer_juggle.env.max_episode_steps ",
        episode, ")"));
  }
  if (absl::StatusOr<std::vector<int>> a = BodyActionIndices(p.body_actions()); !a.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(where("body_actions"), ": ", a.status().message()));
  }
  if (p.rescue().body() && p.body_knot_steps() == 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"rescue"}, {"body"}}),
        ": the rescue searches the whole-body knots, but planner.body_knot_steps is 0 (none)"));
  }
  if (p.cost().impact_acceleration_min() > p.cost().impact_acceleration_max()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"cost"}, {"impact_acceleration_min"}}), ": ",
        p.cost().impact_acceleration_min(), " m/s^2 is above impact_acceleration_max (",
        p.cost().impact_acceleration_max(), "): the band is empty"));
  }
  if (p.replan_every() > p.horizon_steps()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where("replan_every"), ": re-planning every ", p.replan_every(),
                     " steps leaves steps past the horizon of ", p.horizon_steps(),
                     " without a plan"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<PlannerController>> PlannerController::Create(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config) {
  if (absl::Status s = ValidatePlannerConfig(config); !s.ok()) return s;
  auto soccer = std::dynamic_pointer_cast<const JuggleSpec>(spec);
  if (soccer == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat("the planner drives soccer_juggle envs, not ", spec->family()));
  }
  return std::unique_ptr<PlannerController>(
      new PlannerController(std::move(soccer), config.run.planner()));
}

PlannerController::PlannerController(std::shared_ptr<const JuggleSpec> spec,
                                     const config::PlannerConfig& config)
    : spec_(std::move(spec)), config_(config), pool_(spec_, config_.threads()) {}

void PlannerController::Act(const Env* const* envs, const float*, int n, float* actions) {
  for (int i = 0; i < n; ++i) {
    const auto* env = dynamic_cast<const JuggleEnv*>(envs[i]);
    JUGGLE_CHECK(env != nullptr, "the planner controller got an env of another family");
    auto [it, added] = planner_of_.try_emplace(env, static_cast<int>(planners_.size()));
    if (added) {
      planners_.push_back(
          std::make_unique<SoccerPlanner>(spec_, config_, &pool_, planners_.size()));
    }
    SoccerPlanner& planner = *planners_[it->second];
    const int64_t replans = planner.totals().replans;
    const absl::Status s = planner.Act(*env, actions + static_cast<size_t>(i) * kNumActions);
    JUGGLE_CHECK(s.ok(), "the planner's snapshot did not restore into its pool");
    if (on_replan_ && planner.totals().replans != replans) {
      on_replan_(it->second, planner.last_replan());
    }
  }
}

PlannerTotals PlannerController::totals() const {
  PlannerTotals t;
  for (const auto& p : planners_) {
    t.replans += p->totals().replans;
    t.rollouts += p->totals().rollouts;
    t.rollout_steps += p->totals().rollout_steps;
    t.rescues += p->totals().rescues;
    t.prediction_checks += p->totals().prediction_checks;
    t.prediction_mismatches += p->totals().prediction_mismatches;
  }
  return t;
}

}  // namespace juggle::planner
