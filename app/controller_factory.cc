#include "app/controller_factory.h"

#include "absl/strings/str_cat.h"
#include "planner/planner_config.h"

namespace juggle {

absl::StatusOr<std::unique_ptr<Controller>> MakeController(const ControllerChoice& choice,
                                                           std::shared_ptr<const EnvSpec> spec,
                                                           const LoadedConfig& config) {
  if (choice.kind == "zero") return std::make_unique<ZeroController>(spec->act_dim());
  if (choice.kind == "policy") {
    if (choice.policy == nullptr) return absl::InvalidArgumentError("a policy controller needs a policy");
    return std::make_unique<PolicyController>(choice.policy, choice.keep_gates);
  }
  if (choice.kind == "planner") {
    LoadedConfig with_settings = config;
    if (absl::Status s = planner::ApplyPlannerSettings(choice.planner_set, &with_settings);
        !s.ok()) {
      return s;
    }
    if (choice.proposal != nullptr) with_settings.run.mutable_planner()->set_policy_prior(true);
    absl::StatusOr<std::unique_ptr<planner::PlannerController>> p =
        planner::PlannerController::Create(std::move(spec), with_settings,
                                           choice.planner_stream_base);
    if (!p.ok()) return p.status();
    if (choice.proposal != nullptr) {
      if (absl::Status s = (*p)->SetProposal(choice.proposal); !s.ok()) return s;
    }
    if (choice.on_planner) choice.on_planner(p->get());
    return std::unique_ptr<Controller>(std::move(*p));
  }
  return absl::InvalidArgumentError(
      absl::StrCat("no controller named '", choice.kind, "' (policy, zero or planner)"));
}

absl::StatusOr<ControllerFactory> MakeControllerFactory(ControllerChoice choice) {
  LoadedConfig probe;
  if (absl::Status s = planner::ApplyPlannerSettings(choice.planner_set, &probe); !s.ok()) {
    return s;
  }
  return ControllerFactory([choice](std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config) {
    return MakeController(choice, std::move(spec), config);
  });
}

}  // namespace juggle
