// One receding-horizon planner per env (by identity: batches may be compacted as episodes end),
// all on one rollout pool of PlannerConfig.threads threads and one task: what the evaluation
// controller (planner/planner_controller.h) and the worker's labeller
// (planner/planner_labeller.h) share. The planner of the k-th env seen plans on random stream
// stream_base + k. Thread-compatible.
#ifndef JUGGLE_PLANNER_PLANNER_SET_H_
#define JUGGLE_PLANNER_PLANNER_SET_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "planner/planning_task.h"
#include "planner/receding_horizon.h"
#include "planner/rollout_pool.h"

namespace juggle::planner {

class PlannerSet {
 public:
  // Validates config.run.planner (ValidatePlannerConfig) and makes the family's task for `spec`
  // (made from `config`). Errors: the checks', a family without a planning task.
  static absl::StatusOr<std::unique_ptr<PlannerSet>> Create(std::shared_ptr<const EnvSpec> spec,
                                                            const LoadedConfig& config,
                                                            uint64_t stream_base);

  // The planner of `env`, made when `env` is first seen. `index`, if given, receives its order
  // of first sight.
  RecedingHorizonPlanner& For(const Env& env, int* index = nullptr);

  // The action the plans' offsets are added to from now on (null: zero); must outlive the set.
  // Planners made before keep theirs.
  void set_prior(const ActionPrior* prior) { prior_ = prior; }

  // Totals over every planner.
  PlannerTotals totals() const;
  const PlanningTask& task() const { return *task_; }
  const EnvSpec& spec() const { return *spec_; }

 private:
  PlannerSet(std::shared_ptr<const EnvSpec> spec, std::shared_ptr<const PlanningTask> task,
             const config::PlannerConfig& config, uint64_t stream_base);

  std::shared_ptr<const EnvSpec> spec_;
  std::shared_ptr<const PlanningTask> task_;
  config::PlannerConfig config_;
  uint64_t stream_base_;
  const ActionPrior* prior_ = nullptr;
  RolloutPool pool_;
  std::vector<std::unique_ptr<RecedingHorizonPlanner>> planners_;  // in order of first sight
  absl::flat_hash_map<const Env*, int> planner_of_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNER_SET_H_
