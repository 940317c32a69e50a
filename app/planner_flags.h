// The planner's flags of the commands that run a controller (eval, render, simulate):
// --controller=planner uses RunConfig.planner, and --planner-set lays text-format
// PlannerConfig fields over it (sweeps without a config file per setting).
#ifndef JUGGLE_APP_PLANNER_FLAGS_H_
#define JUGGLE_APP_PLANNER_FLAGS_H_

#include <string>

#include <CLI/CLI.hpp>

#include "absl/status/statusor.h"
#include "common/config_loader.h"

namespace juggle {

struct PlannerFlags {
  std::string set;  // text-format PlannerConfig fields
};

// Adds --planner-set to `cmd`.
void AddPlannerFlags(CLI::App* cmd, PlannerFlags* flags);

// Lays the flags' settings over config->run.planner. INVALID_ARGUMENT "--planner-set:1:col:
// ..." for text that does not parse or a value out of range.
absl::Status ApplyPlannerFlags(const PlannerFlags& flags, LoadedConfig* config);

}  // namespace juggle

#endif  // JUGGLE_APP_PLANNER_FLAGS_H_
