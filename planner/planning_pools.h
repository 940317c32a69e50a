// The rollout pools a planner runs on: its search's, on the planning model when
// PlannerConfig.planning_model sets one (envs/planning_model.h), and then one on the executed
// model for the chosen plan (RecedingHorizonPlanner's exact_pool).
#ifndef JUGGLE_PLANNER_PLANNING_POOLS_H_
#define JUGGLE_PLANNER_PLANNING_POOLS_H_

#include <memory>

#include "absl/status/statusor.h"
#include "envs/env.h"
#include "planner/rollout_pool.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

struct PlanningPools {
  std::unique_ptr<RolloutPool> search;  // `threads` threads
  std::unique_ptr<RolloutPool> exact;   // min(threads, 2) threads; null without a planning model
};

// Errors: the planning model's (a timestep factor that does not divide the substeps, a family
// without a planning model), each naming planner.planning_model.
absl::StatusOr<PlanningPools> MakePlanningPools(std::shared_ptr<const EnvSpec> spec,
                                               const config::PlannerConfig& config, int threads);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNING_POOLS_H_
