#include "planner/planner_set.h"

#include <utility>

#include "absl/strings/str_cat.h"

#include "planner/planner_config.h"
#include "planner/proposal_trust_task.h"
#include "planner/tasks.h"

namespace juggle::planner {

absl::StatusOr<std::unique_ptr<PlannerSet>> PlannerSet::Create(std::shared_ptr<const EnvSpec> spec,
                                                               const LoadedConfig& config,
                                                               uint64_t stream_base) {
  if (absl::Status s = ValidatePlannerConfig(config); !s.ok()) return s;
  absl::StatusOr<std::shared_ptr<const PlanningTask>> task =
      MakePlanningTask(spec, config.run.planner());
  if (!task.ok()) return task.status();
  const config::PlannerConfig& planner = config.run.planner();
  if (planner.search_prior_trust()) {  // with policy_prior (ValidatePlannerConfig)
    *task = std::make_shared<const ProposalTrustTask>(*std::move(task), spec->act_dim(),
                                                      planner.prior_trust_sigma());
  }
  absl::StatusOr<PlanningPools> pools =
      MakePlanningPools(spec, config.run.planner(), config.run.planner().threads());
  if (!pools.ok()) {
    return absl::Status(pools.status().code(),
                        absl::StrCat(config.config_path, ": ", pools.status().message()));
  }
  return std::unique_ptr<PlannerSet>(new PlannerSet(
      std::move(spec), *std::move(task), config.run.planner(), stream_base, *std::move(pools)));
}

PlannerSet::PlannerSet(std::shared_ptr<const EnvSpec> spec,
                       std::shared_ptr<const PlanningTask> task,
                       const config::PlannerConfig& config, uint64_t stream_base,
                       PlanningPools pools)
    : spec_(std::move(spec)),
      task_(std::move(task)),
      config_(config),
      stream_base_(stream_base),
      proposal_(config.policy_prior() ? std::make_unique<PolicyPrior>(*spec_) : nullptr),
      pools_(std::move(pools)) {}

absl::Status PlannerSet::SetProposal(const EigenPolicy* policy) {
  if (proposal_ == nullptr) {
    return absl::FailedPreconditionError("a proposal policy needs planner.policy_prior: true");
  }
  return proposal_->Set(policy);
}

absl::Status PlannerSet::SetProposal(std::shared_ptr<const EigenPolicy> policy) {
  if (proposal_ == nullptr) {
    return absl::FailedPreconditionError("a proposal policy needs planner.policy_prior: true");
  }
  return proposal_->Set(std::move(policy));
}

RecedingHorizonPlanner& PlannerSet::For(const Env& env, int* index) {
  auto [it, added] = planner_of_.try_emplace(&env, static_cast<int>(planners_.size()));
  if (added) {
    planners_.push_back(std::make_unique<RecedingHorizonPlanner>(
        task_, config_, pools_.search.get(), stream_base_ + planners_.size(), proposal_.get(),
        pools_.exact.get()));
    planners_.back()->set_rescue_log(rescue_log_);
  }
  if (index != nullptr) *index = it->second;
  return *planners_[it->second];
}

void PlannerSet::set_rescue_log(RescueSampleLog* log) {
  rescue_log_ = log;
  for (const auto& p : planners_) p->set_rescue_log(log);
}

PlannerTotals PlannerSet::totals() const {
  PlannerTotals t;
  for (const auto& p : planners_) t.Add(p->totals());
  return t;
}

}  // namespace juggle::planner
