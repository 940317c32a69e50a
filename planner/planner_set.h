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
#include "common/eigen_policy.h"
#include "planner/planning_pools.h"
#include "planner/planning_task.h"
#include "planner/policy_prior.h"
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

  // With PlannerConfig.policy_prior, every planner's actions are the proposal policy's mean
  // plus its plan's offsets (planner/policy_prior.h). The policy from now on (the caller keeps a
  // raw one alive until the next call; null: none, a zero prior). FAILED_PRECONDITION without
  // policy_prior; INVALID_ARGUMENT for a policy of other sizes than the spec's.
  bool has_proposal() const { return proposal_ != nullptr; }
  absl::Status SetProposal(const EigenPolicy* policy);
  absl::Status SetProposal(std::shared_ptr<const EigenPolicy> policy);

  // Every planner's rescue rollouts, those of planners made later included, are written to
  // `log` (RecedingHorizonPlanner::set_rescue_log; null: none; it must outlive the set).
  void set_rescue_log(RescueSampleLog* log);

  // Totals over every planner.
  PlannerTotals totals() const;
  const PlanningTask& task() const { return *task_; }
  const EnvSpec& spec() const { return *spec_; }

 private:
  PlannerSet(std::shared_ptr<const EnvSpec> spec, std::shared_ptr<const PlanningTask> task,
             const config::PlannerConfig& config, uint64_t stream_base, PlanningPools pools);

  std::shared_ptr<const EnvSpec> spec_;
  std::shared_ptr<const PlanningTask> task_;
  config::PlannerConfig config_;
  uint64_t stream_base_;
  std::unique_ptr<PolicyPrior> proposal_;  // with config.policy_prior
  RescueSampleLog* rescue_log_ = nullptr;
  PlanningPools pools_;
  std::vector<std::unique_ptr<RecedingHorizonPlanner>> planners_;  // in order of first sight
  absl::flat_hash_map<const Env*, int> planner_of_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNER_SET_H_
