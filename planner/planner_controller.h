// The planner as an evaluation controller (eval/controller.h): what `--controller=planner`
// runs in `juggle eval`, `juggle render` and `juggle simulate`. One receding-horizon planner
// per env (planner/planner_set.h; its random stream is the order in which the env was first
// seen), all sharing one rollout pool of RunConfig.planner.threads threads and the family's
// planning task (planner/tasks.h). Thread-compatible.
#ifndef JUGGLE_PLANNER_PLANNER_CONTROLLER_H_
#define JUGGLE_PLANNER_PLANNER_CONTROLLER_H_

#include <functional>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "eval/controller.h"
#include "planner/planner_config.h"
#include "planner/planner_set.h"
#include "planner/receding_horizon.h"

namespace juggle::planner {

class PlannerController final : public Controller {
 public:
  // Refuses a config without a planner block (RequirePlannerBlock) and validates its settings
  // for `spec` (made from `config`; PlannerSet::Create). The k-th env seen plans from stream
  // stream_base + k: an evaluation split into parts passes its first episode's index, so an
  // episode planned in a part (or alone) plans as it did in the whole batch.
  static absl::StatusOr<std::unique_ptr<PlannerController>> Create(
      std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config, uint64_t stream_base = 0);

  // REQUIRES: envs of the spec given to Create (a foreign env aborts: programmer error).
  void Act(const Env* const* envs, const float* obs, int n, float* actions) override;
  std::string name() const override { return "planner"; }

  // The proposal policy (PlannerConfig.policy_prior; PlannerSet::SetProposal).
  absl::Status SetProposal(std::shared_ptr<const EigenPolicy> policy) {
    return planners_->SetProposal(std::move(policy));
  }
  // Every rescue's rollouts to `log` (PlannerSet::set_rescue_log).
  void set_rescue_log(RescueSampleLog* log) { planners_->set_rescue_log(log); }
  // Totals over every env's planner.
  PlannerTotals totals() const { return planners_->totals(); }
  // The planner of `env` (made when `env` is first seen).
  const RecedingHorizonPlanner& PlannerFor(const Env& env) { return planners_->For(env); }
  const PlanningTask& task() const { return planners_->task(); }
  // Called after every re-plan (the env's planner stream, report): progress lines.
  void set_on_replan(std::function<void(int, const ReplanReport&)> f) { on_replan_ = std::move(f); }

 private:
  explicit PlannerController(std::unique_ptr<PlannerSet> planners)
      : planners_(std::move(planners)) {}

  std::unique_ptr<PlannerSet> planners_;
  std::function<void(int, const ReplanReport&)> on_replan_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNER_CONTROLLER_H_
