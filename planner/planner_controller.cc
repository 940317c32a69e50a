#include "planner/planner_controller.h"

#include "common/check.h"

namespace juggle::planner {

absl::StatusOr<std::unique_ptr<PlannerController>> PlannerController::Create(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config, uint64_t stream_base) {
  if (absl::Status s = RequirePlannerBlock(config); !s.ok()) return s;
  absl::StatusOr<std::unique_ptr<PlannerSet>> planners =
      PlannerSet::Create(std::move(spec), config, stream_base);
  if (!planners.ok()) return planners.status();
  return std::unique_ptr<PlannerController>(new PlannerController(*std::move(planners)));
}

void PlannerController::Act(const Env* const* envs, const float*, int n, float* actions) {
  const int act = planners_->spec().act_dim();
  for (int i = 0; i < n; ++i) {
    int slot = 0;
    RecedingHorizonPlanner& planner = planners_->For(*envs[i], &slot);
    const int64_t replans = planner.totals().replans;
    const absl::Status s = planner.Act(*envs[i], actions + static_cast<size_t>(i) * act);
    JUGGLE_CHECK(s.ok(), "the planner's snapshot did not restore into its pool (an env of "
                         "another spec?)");
    if (on_replan_ && planner.totals().replans != replans) on_replan_(slot, planner.last_replan());
  }
}

}  // namespace juggle::planner
