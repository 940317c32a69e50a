// The searched trust in the learned proposal (planner/proposal_trust_task.h) on the smallest
// task (planner/testing/point_mass.h): a plan acts on the prior scaled by its trust, the trust
// shifts with the plan, the seeds can always drop the policy, and a planner searching the
// trust ignores a policy that pushes away from the goal while its predictions still hold.
#include "planner/proposal_trust_task.h"

#include <cmath>
#include <memory>
#include <vector>

#include "gtest/gtest.h"
#include "common/testing/constant_policy.h"
#include "planner/policy_prior.h"
#include "planner/receding_horizon.h"
#include "planner/rollout_pool.h"
#include "planner/testing/point_mass.h"

namespace juggle::planner {
namespace {

using testing::PointMassSpec;
using testing::PointMassTask;
using testing::PointMassTaskSettings;

class ProposalTrustTaskTest : public ::testing::Test {
 protected:
  ProposalTrustTaskTest()
      : spec_(PointMassSpec::Create()),
        inner_(std::make_shared<PointMassTask>(PointMassTaskSettings{})),
        task_(std::make_shared<ProposalTrustTask>(inner_, 2, 0.25)),
        pool_(spec_, 2),
        walk_(&spec_->graph()) {}

  std::shared_ptr<const PointMassSpec> spec_;
  std::shared_ptr<const PointMassTask> inner_;
  std::shared_ptr<const ProposalTrustTask> task_;
  RolloutPool pool_;
  AdaptiveWalk walk_;
};

TEST_F(ProposalTrustTaskTest, APlanActsOnThePriorScaledByItsTrust) {
  ASSERT_EQ(task_->dim(), inner_->dim() + 1);
  EXPECT_EQ(task_->space().lower.back(), 0);
  EXPECT_EQ(task_->space().upper.back(), 1);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  std::vector<double> theta(task_->dim(), 0.0);
  theta[0] = 0.2;  // an offset of the first knot
  const double prior[2] = {0.5, -0.4};
  float inner_action[2], action[2];
  for (double t : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE(t);
    theta.back() = t;
    const double scaled[2] = {t * prior[0], t * prior[1]};
    inner_->Action(*env, theta.data(), {0, 0}, scaled, inner_action);
    task_->Action(*env, theta.data(), {0, 0}, prior, action);
    EXPECT_EQ(action[0], inner_action[0]);
    EXPECT_EQ(action[1], inner_action[1]);
  }
}

TEST_F(ProposalTrustTaskTest, TheTrustShiftsWithThePlanAndTheSeedsCanDropThePolicy) {
  std::vector<double> theta(task_->dim(), 0.1);
  theta.back() = 0.7;
  const std::vector<double> shifted = task_->Shift(theta, 5, 0);
  const std::vector<double> inner_shifted =
      inner_->Shift(std::vector<double>(theta.begin(), theta.end() - 1), 5, 0);
  ASSERT_EQ(shifted.size(), theta.size());
  EXPECT_EQ(std::vector<double>(shifted.begin(), shifted.end() - 1), inner_shifted);
  EXPECT_EQ(shifted.back(), 0.7);
  const std::vector<std::vector<double>> seeds = task_->Seeds(theta);
  ASSERT_EQ(seeds.size(), 2u);
  EXPECT_EQ(seeds[0], theta) << "the warm start first: the incumbent";
  EXPECT_EQ(seeds[1].back(), 0) << "the warm start without the policy";
  std::vector<double> alone(task_->dim(), 0.0);
  alone.back() = 1;
  EXPECT_EQ(task_->ProposalAlone(), alone);
}

// A policy that pushes away from the target at full strength: added to every candidate it
// costs the search, searched as a trust it is dropped, and the predictions stay exact.
TEST_F(ProposalTrustTaskTest, APlannerSearchingTheTrustDropsAPolicyThatPushesAway) {
  PolicyPrior prior(*spec_);
  auto away = std::make_shared<const EigenPolicy>(::juggle::testing::ConstantPolicy(4, 2, -3.0f));
  ASSERT_TRUE(prior.Set(away).ok());
  config::PlannerConfig p;
  p.set_samples(24);
  p.set_iterations(4);
  p.set_replan_every(5);
  p.set_seed(1);
  RecedingHorizonPlanner planner(task_, p, &pool_, 0, &prior);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  for (int t = 0; t < 150; ++t) {
    ASSERT_TRUE(planner.Act(*env, a).ok());
    env->Step(a, walk_);
  }
  const double* q = env->data()->qpos;
  EXPECT_NEAR(q[0], 0.3, 0.05);
  EXPECT_NEAR(q[1], -0.2, 0.05);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  EXPECT_EQ(planner.totals().proposal_tried, planner.totals().replans);
  EXPECT_EQ(planner.totals().proposal_chosen, 0) << "the policy alone pushes away";
  EXPECT_LT(planner.totals().proposal_weight_sum / planner.totals().proposal_tried, 0.25)
      << "the chosen plans take little of it";
}

}  // namespace
}  // namespace juggle::planner
