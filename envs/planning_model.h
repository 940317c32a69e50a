// A planning model: the executed model with cheaper simulation options, for the planner's
// rollouts (PlannerConfig.planning_model, docs/planner.md "Planning model"). Its spec shares
// the exact spec's fingerprint, so its envs restore the exact envs' snapshots: the state is the
// same, only how it advances differs.
#ifndef JUGGLE_ENVS_PLANNING_MODEL_H_
#define JUGGLE_ENVS_PLANNING_MODEL_H_

#include <memory>

#include "absl/status/statusor.h"
#include "envs/env.h"

namespace juggle {

struct PlanningModelOptions {
  int timestep_factor = 1;      // timestep × this, substeps ÷ this (must divide them)
  int solver_iterations = 0;    // constraint solver iterations (0: the model's)
  double solver_tolerance = 0;  // solver tolerance (0: the model's)
  bool pyramidal_cone = false;  // pyramidal friction cones instead of the model's
  bool changes_nothing() const {
    return timestep_factor == 1 && solver_iterations == 0 && solver_tolerance == 0 &&
           !pyramidal_cone;
  }
};

// The planning variant of `exact`. INVALID_ARGUMENT when the timestep factor does not divide
// the control step's substeps; UNIMPLEMENTED for families without one (only soccer_juggle has).
absl::StatusOr<std::shared_ptr<const EnvSpec>> CreatePlanningSpec(
    const std::shared_ptr<const EnvSpec>& exact, const PlanningModelOptions& options);

}  // namespace juggle

#endif  // JUGGLE_ENVS_PLANNING_MODEL_H_
