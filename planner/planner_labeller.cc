#include "planner/planner_labeller.h"

#include <memory>
#include <utility>

#include "planner/planner_set.h"

namespace juggle {
namespace {

using planner::PlannerSet;

class PlannerLabeller final : public Labeller {
 public:
  explicit PlannerLabeller(std::unique_ptr<PlannerSet> planners)
      : planners_(std::move(planners)) {}

  absl::Status Label(const Env& env, float* action) override {
    return planners_->For(env).Act(env, action);
  }

  // With planner.policy_prior the acting policy is the planners' proposal (expert iteration:
  // the planner labels with the policy it improves).
  absl::Status SetPolicy(const EigenPolicy* policy) override {
    return planners_->has_proposal() ? planners_->SetProposal(policy) : absl::OkStatus();
  }

 private:
  std::unique_ptr<PlannerSet> planners_;
};

}  // namespace

absl::StatusOr<std::unique_ptr<Labeller>> MakePlannerLabeller(std::shared_ptr<const EnvSpec> spec,
                                                              const LoadedConfig& config,
                                                              int worker) {
  absl::StatusOr<std::unique_ptr<PlannerSet>> planners =
      PlannerSet::Create(std::move(spec), config, uint64_t(worker) << 16);
  if (!planners.ok()) return planners.status();
  return std::unique_ptr<Labeller>(std::make_unique<PlannerLabeller>(*std::move(planners)));
}

}  // namespace juggle
