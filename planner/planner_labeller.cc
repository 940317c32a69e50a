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

  ExpertCounters TakeCounters() override {
    const planner::PlannerTotals now = planners_->totals();
    ExpertCounters c;
    c.replans = now.replans - taken_.replans;
    c.rollout_steps = now.rollout_steps + now.exact_rollout_steps -
                      (taken_.rollout_steps + taken_.exact_rollout_steps);
    c.rescues = now.rescues - taken_.rescues;
    c.proposal_tried = now.proposal_tried - taken_.proposal_tried;
    c.proposal_chosen = now.proposal_chosen - taken_.proposal_chosen;
    c.proposal_weight_sum = now.proposal_weight_sum - taken_.proposal_weight_sum;
    taken_ = now;
    return c;
  }

 private:
  std::unique_ptr<PlannerSet> planners_;
  planner::PlannerTotals taken_;  // the totals at the previous TakeCounters
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
