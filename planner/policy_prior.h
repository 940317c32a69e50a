// A policy's mean action as the prior the plan's offsets are added to (planner/planning_task.h,
// ActionPrior; PlannerConfig.policy_prior): the learned policy proposes, the search corrects.
// The policy reads the env's observation at every state a rollout visits; without a policy the
// prior is zero. Write is thread-safe (EigenPolicy's forward pass is const); Set must not run
// while a rollout may call Write (call it between re-plans).
#ifndef JUGGLE_PLANNER_POLICY_PRIOR_H_
#define JUGGLE_PLANNER_POLICY_PRIOR_H_

#include <memory>

#include "absl/status/status.h"
#include "common/eigen_policy.h"
#include "envs/env.h"
#include "planner/planning_task.h"

namespace juggle::planner {

class PolicyPrior final : public ActionPrior {
 public:
  // For envs of `spec` (REQUIRES: spec outlives the prior).
  explicit PolicyPrior(const EnvSpec& spec) : spec_(spec) {}

  // The policy from now on: `policy` (the caller keeps it alive until the next Set), or none
  // (zero). INVALID_ARGUMENT, nothing changed, when its observation or action size differs from
  // the spec's.
  absl::Status Set(const EigenPolicy* policy);
  // The same, owning the policy.
  absl::Status Set(std::shared_ptr<const EigenPolicy> policy);
  bool has_policy() const { return policy_ != nullptr; }

  void Write(const Env& env, double* prior) const override;
  bool proposes() const override { return has_policy(); }

 private:
  const EnvSpec& spec_;
  const EigenPolicy* policy_ = nullptr;
  std::shared_ptr<const EigenPolicy> owned_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_POLICY_PRIOR_H_
