// A policy's mean action as the prior the plan's offsets are added to (planner/planning_task.h,
// ActionPrior): the learned policy proposes, the search corrects (issue 48). The policy reads
// the env's observation at every state a rollout visits. Thread-safe (EigenPolicy's forward
// pass is const).
#ifndef JUGGLE_PLANNER_POLICY_PRIOR_H_
#define JUGGLE_PLANNER_POLICY_PRIOR_H_

#include <memory>

#include "absl/status/statusor.h"
#include "common/eigen_policy.h"
#include "envs/env.h"
#include "planner/planning_task.h"

namespace juggle::planner {

class PolicyPrior final : public ActionPrior {
 public:
  // INVALID_ARGUMENT when the policy's observation or action size differs from `spec`'s.
  static absl::StatusOr<std::unique_ptr<PolicyPrior>> Create(
      std::shared_ptr<const EigenPolicy> policy, const EnvSpec& spec);
  void Write(const Env& env, double* prior) const override;

 private:
  explicit PolicyPrior(std::shared_ptr<const EigenPolicy> policy) : policy_(std::move(policy)) {}
  std::shared_ptr<const EigenPolicy> policy_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_POLICY_PRIOR_H_
