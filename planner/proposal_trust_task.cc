#include "planner/proposal_trust_task.h"

#include <algorithm>
#include <utility>

#include "absl/container/inlined_vector.h"

namespace juggle::planner {
namespace {

SearchSpace WithTrust(SearchSpace space, double sigma) {
  space.lower.push_back(0);
  space.upper.push_back(1);
  space.sigma.push_back(sigma);
  return space;
}

}  // namespace

ProposalTrustTask::ProposalTrustTask(std::shared_ptr<const PlanningTask> inner, int act_dim,
                                     double sigma)
    : inner_(std::move(inner)),
      act_dim_(act_dim),
      space_(WithTrust(inner_->space(), sigma)),
      rescue_space_(WithTrust(inner_->rescue_space(), std::min(1.0, 2 * sigma))) {}

SearchSpace ProposalTrustTask::RescueSpaceAt(const Env& env) const {
  return WithTrust(inner_->RescueSpaceAt(env), rescue_space_.sigma.back());  // the trust's
}

std::vector<double> ProposalTrustTask::Shift(const std::vector<double>& theta, int grid_steps,
                                             int cycles) const {
  return With(inner_->Shift(Inner(theta), grid_steps, cycles), trust(theta.data()));
}

std::vector<std::vector<double>> ProposalTrustTask::Seeds(const std::vector<double>& start) const {
  std::vector<std::vector<double>> seeds;
  for (std::vector<double>& s : inner_->Seeds(Inner(start))) {
    seeds.push_back(With(std::move(s), trust(start.data())));
  }
  // The warm start without the policy: the search can always drop it.
  if (trust(start.data()) != 0) seeds.push_back(With(Inner(start), 0));
  return seeds;
}

std::vector<double> ProposalTrustTask::ProposalAlone() const {
  return With(std::vector<double>(inner_->dim(), 0.0), 1);
}

double ProposalTrustTask::PriorWeight(const double* theta) const {
  return std::clamp(trust(theta), 0.0, 1.0);
}

void ProposalTrustTask::Restrict(const Env& env, const std::vector<double>& shifted,
                                 SearchSpace* space, std::vector<std::vector<double>>* seeds) const {
  const int n = inner_->dim();
  SearchSpace inner_space;
  inner_space.lower.assign(space->lower.begin(), space->lower.begin() + n);
  inner_space.upper.assign(space->upper.begin(), space->upper.begin() + n);
  inner_space.sigma.assign(space->sigma.begin(), space->sigma.begin() + n);
  std::vector<std::vector<double>> inner_seeds;
  for (const std::vector<double>& s : *seeds) inner_seeds.push_back(Inner(s));
  inner_->Restrict(env, Inner(shifted), &inner_space, &inner_seeds);
  std::copy(inner_space.lower.begin(), inner_space.lower.end(), space->lower.begin());
  std::copy(inner_space.upper.begin(), inner_space.upper.end(), space->upper.begin());
  std::copy(inner_space.sigma.begin(), inner_space.sigma.end(), space->sigma.begin());
  for (size_t i = 0; i < seeds->size(); ++i) {
    std::copy(inner_seeds[i].begin(), inner_seeds[i].end(), (*seeds)[i].begin());
  }
}

double ProposalTrustTask::PlanCost(const double* theta, const std::vector<double>& warm,
                                   bool has_warm) const {
  return inner_->PlanCost(theta, Inner(warm), has_warm);
}

void ProposalTrustTask::Action(const Env& env, const double* theta, PlanClock clock,
                               const double* prior, float* action) const {
  if (prior == nullptr) {
    inner_->Action(env, theta, clock, nullptr, action);
    return;
  }
  // Called at every rollout step: no heap allocation for the character's action sizes.
  const double t = PriorWeight(theta);
  absl::InlinedVector<double, 64> scaled(prior, prior + act_dim_);
  for (double& p : scaled) p *= t;
  inner_->Action(env, theta, clock, scaled.data(), action);
}

}  // namespace juggle::planner
