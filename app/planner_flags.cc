#include "app/planner_flags.h"

#include "planner/planner_config.h"

namespace juggle {

void AddPlannerFlags(CLI::App* cmd, PlannerFlags* flags) {
  cmd->add_option("--planner-set", flags->set,
                  "planner settings over the config's, text format (e.g. 'samples: 64 "
                  "horizon_steps: 45 soccer_juggle { cost { kick: 20 } }'; docs/planner.md)");
}

absl::Status ApplyPlannerFlags(const PlannerFlags& flags, LoadedConfig* config) {
  return planner::ApplyPlannerSettings(flags.set, config);
}

}  // namespace juggle
