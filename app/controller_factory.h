// The one place that builds what acts in an env by name, for every command that runs a
// controller (eval and its force sweep, render, simulate; the live page next): a policy's mean
// action, the zero-action baseline, or the planner (planner/planner_controller.h).
#ifndef JUGGLE_APP_CONTROLLER_FACTORY_H_
#define JUGGLE_APP_CONTROLLER_FACTORY_H_

#include <functional>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "eval/controller.h"
#include "planner/planner_controller.h"

namespace juggle {

struct ControllerChoice {
  std::string kind;  // "policy", "zero" or "planner"
  // "policy": the policy, and whether its controller keeps the gate weights (eval's Eq. 4).
  std::shared_ptr<const EigenPolicy> policy;
  bool keep_gates = false;
  // "planner": text-format PlannerConfig fields laid over each config given (--planner-set;
  // empty when the caller laid them already), and a hook called with each planner made
  // (progress lines, totals).
  std::string planner_set;
  std::function<void(planner::PlannerController*)> on_planner;
  // "planner": a policy whose mean action is the plans' prior (sets planner.policy_prior), or
  // none.
  std::shared_ptr<const EigenPolicy> proposal;
  // "planner": the planner stream of the first env seen (PlannerController::Create); eval's
  // --first-episode, so that a part of an evaluation plans as the whole did.
  uint64_t planner_stream_base = 0;
};

// The controller `choice` names for envs of `spec` (made from `config`). Errors: an unknown
// kind, a policy kind without a policy, the planner's (a config without a planner block, its
// settings, a family without a planning task).
absl::StatusOr<std::unique_ptr<Controller>> MakeController(const ControllerChoice& choice,
                                                           std::shared_ptr<const EnvSpec> spec,
                                                           const LoadedConfig& config);

// The same as a factory for tools that make their env specs themselves (render, the force
// sweep). The planner settings are checked here, once.
absl::StatusOr<ControllerFactory> MakeControllerFactory(ControllerChoice choice);

}  // namespace juggle

#endif  // JUGGLE_APP_CONTROLLER_FACTORY_H_
