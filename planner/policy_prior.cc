#include "planner/policy_prior.h"

#include <vector>

#include "absl/strings/str_cat.h"

namespace juggle::planner {

absl::StatusOr<std::unique_ptr<PolicyPrior>> PolicyPrior::Create(
    std::shared_ptr<const EigenPolicy> policy, const EnvSpec& spec) {
  if (policy->obs_dim() != spec.obs_dim() || policy->act_dim() != spec.act_dim()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the proposal policy reads ", policy->obs_dim(), " observations and writes ",
        policy->act_dim(), " actions, but the planner's ", spec.family(), " envs have ",
        spec.obs_dim(), " and ", spec.act_dim()));
  }
  return std::unique_ptr<PolicyPrior>(new PolicyPrior(std::move(policy)));
}

void PolicyPrior::Write(const Env& env, double* prior) const {
  std::vector<float> obs(policy_->obs_dim());
  env.WriteObservation(obs.data());
  const RowMatrix mean = policy_->MeanActions(obs.data(), 1);
  for (int i = 0; i < policy_->act_dim(); ++i) prior[i] = mean(0, i);
}

}  // namespace juggle::planner
