#include "app/planner_flags.h"

#include "planner/planner_controller.h"

namespace juggle {

void AddPlannerFlags(CLI::App* cmd, PlannerFlags* flags) {
  cmd->add_option("--planner-set", flags->set,
                  "planner settings over the config's, text format (e.g. 'samples: 64 "
                  "horizon_steps: 45 cost { kick: 20 }'; docs/planner.md)");
}

absl::Status ApplyPlannerFlags(const PlannerFlags& flags, LoadedConfig* config) {
  return planner::ApplyPlannerSettings(flags.set, config);
}

absl::StatusOr<ControllerFactory> PlannerControllerFactory(const PlannerFlags& flags) {
  LoadedConfig probe;
  if (absl::Status s = ApplyPlannerFlags(flags, &probe); !s.ok()) return s;
  return ControllerFactory([flags](std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config)
                               -> absl::StatusOr<std::unique_ptr<Controller>> {
    LoadedConfig with_flags = config;
    if (absl::Status s = ApplyPlannerFlags(flags, &with_flags); !s.ok()) return s;
    absl::StatusOr<std::unique_ptr<planner::PlannerController>> p =
        planner::PlannerController::Create(std::move(spec), with_flags);
    if (!p.ok()) return p.status();
    return std::unique_ptr<Controller>(std::move(*p));
  });
}

}  // namespace juggle
