// A planning task whose plans also choose how much of the learned proposal they take (issue
// 48; PlannerConfig.search_prior_trust): the inner task's variables, then one more, the trust
// t in [0, 1]; a plan acts as the inner task's plan on the prior scaled by t. So the search
// compares the policy, the search without it and blends of the two by their simulated cost,
// as generative predictive control lets a policy's samples compete with the planner's: a
// policy that does not help is not taken, instead of being added to every candidate.
// Seeds: the inner task's at the warm start's trust, and the warm start without the policy
// (t = 0); ProposalAlone is zero offsets at t = 1. Everything else is the inner task's.
#ifndef JUGGLE_PLANNER_PROPOSAL_TRUST_TASK_H_
#define JUGGLE_PLANNER_PROPOSAL_TRUST_TASK_H_

#include <memory>
#include <string>
#include <vector>

#include "planner/planning_task.h"

namespace juggle::planner {

class ProposalTrustTask final : public PlanningTask {
 public:
  // `act_dim`: the actions of the inner task's envs. `sigma`: the trust's initial spread (the
  // rescue search's is twice it, up to 1).
  ProposalTrustTask(std::shared_ptr<const PlanningTask> inner, int act_dim, double sigma);

  std::string family() const override { return inner_->family(); }
  const SearchSpace& space() const override { return space_; }
  const SearchSpace& rescue_space() const override { return rescue_space_; }
  SearchSpace RescueSpaceAt(const Env& env) const override;
  int horizon() const override { return inner_->horizon(); }
  int max_run_on_steps() const override { return inner_->max_run_on_steps(); }
  int KnotAtOrBefore(int step) const override { return inner_->KnotAtOrBefore(step); }
  bool StartsCycle(const Env& env, int node) const override {
    return inner_->StartsCycle(env, node);
  }
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override;
  std::vector<std::vector<double>> Seeds(const std::vector<double>& start) const override;
  std::vector<double> ProposalAlone() const override;
  double PriorWeight(const double* theta) const override;
  void Restrict(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                std::vector<std::vector<double>>* seeds) const override;
  double ContactClearance(const Env& env) const override { return inner_->ContactClearance(env); }
  double PlanCost(const double* theta, const std::vector<double>& warm,
                  bool has_warm) const override;
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  std::unique_ptr<RolloutScorer> NewScorer() const override { return inner_->NewScorer(); }
  std::vector<std::string> term_names() const override { return inner_->term_names(); }
  std::vector<std::string> outcome_names() const override { return inner_->outcome_names(); }
  std::optional<VariableBlock> RefineBlock(const Env& env) const override {
    return inner_->RefineBlock(env);
  }
  int num_residuals() const override { return inner_->num_residuals(); }
  bool Residuals(const std::vector<double>& outcome, double* residuals) const override {
    return inner_->Residuals(outcome, residuals);
  }
  double refine_prior_weight() const override { return inner_->refine_prior_weight(); }
  std::optional<VariableBlock> ActingBlock(PlanClock clock) const override {
    return inner_->ActingBlock(clock);
  }
  const float* AppliedAction(const Env& env) const override { return inner_->AppliedAction(env); }
  int decision_size() const override { return inner_->decision_size(); }
  std::string DescribeDecision(const std::vector<double>& decision,
                               const std::vector<double>& outcome) const override {
    return inner_->DescribeDecision(decision, outcome);
  }

  // The trust of plan `theta` (its last variable).
  double trust(const double* theta) const { return theta[inner_->dim()]; }

 private:
  std::vector<double> Inner(const std::vector<double>& theta) const {
    return std::vector<double>(theta.begin(), theta.begin() + inner_->dim());
  }
  std::vector<double> With(std::vector<double> inner, double trust) const {
    inner.push_back(trust);
    return inner;
  }

  std::shared_ptr<const PlanningTask> inner_;
  int act_dim_;
  SearchSpace space_, rescue_space_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PROPOSAL_TRUST_TASK_H_
