// THE list of planning tasks (planner/tasks.cc: one entry per env family that has one, no
// static self-registration, beside the env families' list in envs/registry.cc), and the
// functions that check a run's planner settings and make its task through that list.
#ifndef JUGGLE_PLANNER_TASKS_H_
#define JUGGLE_PLANNER_TASKS_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "planner/planning_task.h"

namespace juggle::planner {

struct PlanningTaskEntry {
  std::string family;  // the env family, as EnvSpec::family()
  // OK, or INVALID_ARGUMENT "file:line:col: planner.<field>: ..." for the task's settings.
  absl::Status (*validate)(const LoadedConfig& config);
  // The task for envs of `spec` (of this family), from validated settings.
  std::shared_ptr<const PlanningTask> (*make)(std::shared_ptr<const EnvSpec> spec,
                                              const config::PlannerConfig& config);
  // The task has a refinement (PlanningTask::RefineBlock and residuals), which
  // planner.refine_iterations and planner.rescue.refine_first need (else a config error).
  bool refines = false;
  // The task's cost has a later-kicks part (PlanningTask's later cost), which
  // planner.rescue.ignore_later_kicks needs (else a config error).
  bool has_later_kicks = false;
  // The task's plan carries planner.body_knot_steps' whole-body knots; without them a config
  // that asks for knots (BodyKnotRequest, planner/planner_config.h) is an error, not ignored.
  bool body_knots = false;
};

// Every task, in the order of planner/tasks.cc.
const std::vector<PlanningTaskEntry>& PlanningTasks();
// "soccer_juggle" (comma-separated when several): the families that have a task, for messages.
std::string FamiliesWithPlanningTasks();

// The entry of `family`; INVALID_ARGUMENT naming the families that have one when it has none.
absl::StatusOr<const PlanningTaskEntry*> PlanningTaskFor(const std::string& family);

// The task for envs of `spec` with `config`'s settings. REQUIRES: config passed
// ValidatePlannerConfig (planner/planner_config.h). Errors: a family without a task.
absl::StatusOr<std::shared_ptr<const PlanningTask>> MakePlanningTask(
    std::shared_ptr<const EnvSpec> spec, const config::PlannerConfig& config);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_TASKS_H_
