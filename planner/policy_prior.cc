#include "planner/policy_prior.h"

#include <algorithm>
#include <vector>

#include "absl/strings/str_cat.h"

namespace juggle::planner {

absl::Status PolicyPrior::Set(const EigenPolicy* policy) {
  if (policy != nullptr &&
      (policy->obs_dim() != spec_.obs_dim() || policy->act_dim() != spec_.act_dim())) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the proposal policy reads ", policy->obs_dim(), " observations and writes ",
        policy->act_dim(), " actions, but the planner's ", spec_.family(), " envs have ",
        spec_.obs_dim(), " and ", spec_.act_dim()));
  }
  policy_ = policy;
  owned_.reset();
  return absl::OkStatus();
}

absl::Status PolicyPrior::Set(std::shared_ptr<const EigenPolicy> policy) {
  if (absl::Status s = Set(policy.get()); !s.ok()) return s;
  owned_ = std::move(policy);
  return absl::OkStatus();
}

void PolicyPrior::Write(const Env& env, double* prior) const {
  const int act = spec_.act_dim();
  if (policy_ == nullptr) {
    std::fill(prior, prior + act, 0.0);
    return;
  }
  std::vector<float> obs(spec_.obs_dim());
  env.WriteObservation(obs.data());
  const RowMatrix mean = policy_->MeanActions(obs.data(), 1);
  for (int i = 0; i < act; ++i) prior[i] = mean(0, i);
}

}  // namespace juggle::planner
