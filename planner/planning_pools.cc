#include "planner/planning_pools.h"

#include <algorithm>
#include <utility>

#include "envs/planning_model.h"

namespace juggle::planner {

absl::StatusOr<PlanningPools> MakePlanningPools(std::shared_ptr<const EnvSpec> spec,
                                               const config::PlannerConfig& config, int threads) {
  PlanningPools pools;
  PlanningModelOptions options;
  if (config.has_planning_model()) {
    const config::PlanningModel& m = config.planning_model();
    options.timestep_factor = m.timestep_factor();
    options.solver_iterations = m.solver_iterations();
    options.solver_tolerance = m.solver_tolerance();
    options.pyramidal_cone = m.pyramidal_cone();
  }
  if (options.changes_nothing()) {
    pools.search = std::make_unique<RolloutPool>(std::move(spec), threads);
    return pools;
  }
  absl::StatusOr<std::shared_ptr<const EnvSpec>> planning = CreatePlanningSpec(spec, options);
  if (!planning.ok()) return planning.status();
  const bool multi_fidelity = config.planning_model().exact_within_m() > 0;
  pools.search = std::make_unique<RolloutPool>(*std::move(planning), threads,
                                               multi_fidelity ? spec : nullptr);
  // The chosen plan and the warm start run side by side (check_on_exact).
  pools.exact = std::make_unique<RolloutPool>(std::move(spec), std::min(threads, 2));
  return pools;
}

}  // namespace juggle::planner
