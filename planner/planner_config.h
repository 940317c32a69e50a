// Checks of a run's planner settings (RunConfig.planner, proto/planner.proto) beyond the
// schema's ranges, and the `--planner-set` overlay. Generic settings are checked here, the
// task's own by its entry in planner/tasks.cc.
#ifndef JUGGLE_PLANNER_PLANNER_CONFIG_H_
#define JUGGLE_PLANNER_PLANNER_CONFIG_H_

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "common/config_loader.h"
#include "common/source_locator.h"

namespace juggle::planner {

// OK, or INVALID_ARGUMENT "file:line:col: planner.<field>: ..." for settings the schema's
// ranges allow but the run does not: a family without a planning task, a task block of another
// family, re-planning past the horizon, a rescue of body knots without knots, and the task's own
// checks. (planner.kick and planner.cost, which moved into the soccer task's block, are moved
// there when the config loads: common/config_loader.cc.)
absl::Status ValidatePlannerConfig(const LoadedConfig& config);

// The setting of `p` that asks for whole-body knots — body_knot_steps set above 0 (its default
// of 12, unset, asks for nothing), body_actions, rescue.body — as its path from `planner`, or
// none. A task whose plan has no such knots refuses it (PlanningTaskEntry::body_knots).
std::optional<FieldPath> BodyKnotRequest(const config::PlannerConfig& p);

// OK when `config` has a planner block. Otherwise INVALID_ARGUMENT naming the config and the
// documented planner configs: `--controller=planner` never runs on silent defaults.
absl::Status RequirePlannerBlock(const LoadedConfig& config);

// Lays `text` (text-format PlannerConfig fields, e.g. "samples: 8 iterations: 2") over
// config->run.planner; empty text changes nothing. INVALID_ARGUMENT "--planner-set:1:col: ..."
// for text that does not parse or a value out of range. `kick { }` and `cost { }` go to
// soccer_juggle's block, where they moved (both places at once: INVALID_ARGUMENT).
absl::Status ApplyPlannerSettings(const std::string& text, LoadedConfig* config);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNER_CONFIG_H_
