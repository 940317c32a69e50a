// The receding-horizon driver on the smallest task (planner/testing/point_mass.h): it finds the
// optimum, is deterministic for a seed, its warm-start shift is exact, its rescue runs only above
// its threshold and never raises the cost, its predictions hold bit for bit, a prior action is
// added under the plan, and a family without a planning task is a clear error.
#include "planner/receding_horizon.h"

#include <cmath>
#include <memory>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "common/testing/constant_policy.h"
#include "planner/policy_prior.h"
#include "planner/tasks.h"
#include "planner/testing/point_mass.h"

namespace juggle::planner {
namespace {

using testing::PointMassSpec;
using testing::PointMassTask;
using testing::PointMassTaskSettings;
using ::testing::HasSubstr;

config::PlannerConfig SmallSearch(uint64_t seed = 1) {
  config::PlannerConfig p;
  p.set_samples(24);
  p.set_iterations(4);
  p.set_replan_every(5);
  p.set_seed(seed);
  return p;
}

class RecedingHorizonTest : public ::testing::Test {
 protected:
  RecedingHorizonTest()
      : spec_(PointMassSpec::Create()),
        task_(std::make_shared<PointMassTask>(PointMassTaskSettings{})),
        pool_(spec_, 2),
        walk_(&spec_->graph()) {}

  // Runs `planner` from rest for `steps` control steps; returns the actions it chose.
  std::vector<float> Drive(RecedingHorizonPlanner* planner, int steps,
                           std::unique_ptr<Env>* out = nullptr) {
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
    env->Reset(walk_);
    std::vector<float> actions;
    float a[2];
    for (int t = 0; t < steps; ++t) {
      EXPECT_TRUE(planner->Act(*env, a).ok());
      actions.insert(actions.end(), a, a + 2);
      env->Step(a, walk_);
    }
    if (out != nullptr) *out = std::move(env);
    return actions;
  }

  std::shared_ptr<const PointMassSpec> spec_;
  std::shared_ptr<const PointMassTask> task_;
  RolloutPool pool_;
  AdaptiveWalk walk_;
};

TEST_F(RecedingHorizonTest, DrivesThePointMassToItsTargetAndStopsThere) {
  RecedingHorizonPlanner planner(task_, SmallSearch(), &pool_, 0);
  std::unique_ptr<Env> env;
  Drive(&planner, 150, &env);
  const double* q = env->data()->qpos;
  const double* v = env->data()->qvel;
  EXPECT_NEAR(q[0], 0.3, 0.03);
  EXPECT_NEAR(q[1], -0.2, 0.03);
  EXPECT_LT(std::hypot(v[0], v[1]), 0.1);
  EXPECT_EQ(planner.totals().replans, 30);
  EXPECT_GT(planner.totals().prediction_checks, 100);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  // Its terms are named and add up to its cost.
  const ReplanReport& r = planner.last_replan();
  ASSERT_EQ(r.terms.size(), task_->term_names().size());
  EXPECT_NEAR(r.terms[0] + r.terms[1] + r.terms[2], r.best_cost, 1e-9 * (1 + r.best_cost));
}

TEST_F(RecedingHorizonTest, TheChosenPlanIsReadFromItsSearchRolloutNotSimulatedAgain) {
  // One re-plan from rest: its rollouts are the search's evaluations only, and what it reports
  // about its plan is what a fresh rollout of that plan gives.
  RecedingHorizonPlanner planner(task_, SmallSearch(), &pool_, 0);
  std::unique_ptr<Env> start = spec_->NewEnv(Rng(1));
  start->Reset(walk_);
  Drive(&planner, 1);
  const ReplanReport& r = planner.last_replan();
  EXPECT_EQ(planner.totals().replans, 1);
  EXPECT_EQ(planner.totals().rollouts, r.evaluations);
  absl::StatusOr<double> fresh = planner.Evaluate(*start, planner.plan(), nullptr);
  ASSERT_TRUE(fresh.ok());
  EXPECT_EQ(*fresh, r.best_cost);  // the point mass has no plan cost
  ASSERT_EQ(r.terms.size(), task_->term_names().size());
  EXPECT_NEAR(r.terms[0] + r.terms[1] + r.terms[2], *fresh, 1e-9 * (1 + *fresh));
  // The prediction read from the search holds bit for bit over the steps to the next re-plans.
  Drive(&planner, 60);
  EXPECT_GT(planner.totals().prediction_checks, 40);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
}

TEST_F(RecedingHorizonTest, ReplansThatNoLongerPayComeLessOftenAndTheTargetIsStillReached) {
  config::PlannerConfig p = SmallSearch();
  p.set_replan_every_max(20);
  p.set_replan_gain(0.5);
  RecedingHorizonPlanner planner(task_, p, &pool_, 0);
  std::unique_ptr<Env> env;
  Drive(&planner, 150, &env);
  // Every 5 steps would be 30 re-plans; once the mass nears the target, a re-plan rarely halves
  // its warm start's cost.
  EXPECT_LT(planner.totals().replans, 20);
  EXPECT_GE(planner.totals().replans, 8);
  EXPECT_NEAR(env->data()->qpos[0], 0.3, 0.03);
  EXPECT_NEAR(env->data()->qpos[1], -0.2, 0.03);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  // Off (the default), the interval stays replan_every.
  RecedingHorizonPlanner fixed(task_, SmallSearch(), &pool_, 0);
  Drive(&fixed, 150);
  EXPECT_EQ(fixed.totals().replans, 30);
}

TEST_F(RecedingHorizonTest, ALightReplanKeepsAHealthyPlanAndEverySearchEveryReplanSearches) {
  config::PlannerConfig p = SmallSearch();
  p.set_search_every(3);
  p.set_search_skip_below(1e9);  // every warm start is healthy
  RecedingHorizonPlanner planner(task_, p, &pool_, 0);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  int replans = 0;
  for (int t = 0; t < 150; ++t) {
    const int64_t rollouts = planner.totals().rollouts;
    ASSERT_TRUE(planner.Act(*env, a).ok());
    env->Step(a, walk_);
    if (planner.totals().replans == replans) continue;
    replans = static_cast<int>(planner.totals().replans);
    const ReplanReport& r = planner.last_replan();
    // The first re-plan has no plan to keep; then two kept for each search.
    const bool searches = replans % 3 == 1;
    EXPECT_EQ(r.light, !searches) << "re-plan " << replans;
    if (searches) {
      EXPECT_GT(r.evaluations, 20) << "re-plan " << replans;
    } else {
      EXPECT_EQ(r.evaluations, 1) << "re-plan " << replans;
      EXPECT_EQ(planner.totals().rollouts - rollouts, 1) << "re-plan " << replans;
      EXPECT_EQ(r.best_cost, r.incumbent_cost) << "re-plan " << replans;
    }
  }
  EXPECT_EQ(planner.totals().replans, 30);
  EXPECT_EQ(planner.totals().light_replans, 20);
  // A kept plan's prediction holds like a searched one's.
  EXPECT_GT(planner.totals().prediction_checks, 100);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
}

TEST_F(RecedingHorizonTest, LightReplansInAWindowComeOnlyThatManyReplansAfterARescue) {
  config::PlannerConfig p = SmallSearch();
  p.set_search_every(1000);
  p.set_search_skip_below(1e9);  // every warm start is healthy
  p.set_light_from(2);
  p.set_light_to(4);
  // No rescue: no window, every re-plan searches.
  RecedingHorizonPlanner never(task_, p, &pool_, 0);
  Drive(&never, 60);
  EXPECT_EQ(never.totals().light_replans, 0);
  // A rescue at every re-plan whose search leaves more than 0.05 (from rest: the first ones).
  p.mutable_rescue()->set_cost_above(0.05);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  RecedingHorizonPlanner planner(task_, p, &pool_, 0);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  int replans = 0;
  int after_rescue = -1;  // -1: no rescue yet
  int light = 0;
  for (int t = 0; t < 150; ++t) {
    ASSERT_TRUE(planner.Act(*env, a).ok());
    env->Step(a, walk_);
    if (planner.totals().replans == replans) continue;
    replans = static_cast<int>(planner.totals().replans);
    if (after_rescue >= 0) ++after_rescue;
    const ReplanReport& r = planner.last_replan();
    const bool in_window = after_rescue >= 2 && after_rescue < 4;
    EXPECT_EQ(r.light, in_window) << "re-plan " << replans << ", " << after_rescue
                                  << " after a rescue";
    if (r.rescued) after_rescue = 0;
    light += r.light;
  }
  EXPECT_GT(planner.totals().rescues, 0);
  EXPECT_GT(light, 0);
  EXPECT_EQ(planner.totals().light_replans, light);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
}

TEST_F(RecedingHorizonTest, LightReplansWhoseBarNoWarmStartMeetsChangeNothing) {
  // Every warm start costs more than the bar: each re-plan searches as without light re-plans,
  // and the warm start's rollout is read by the search, so the rollouts are the same too.
  config::PlannerConfig p = SmallSearch();
  p.set_search_every(3);
  p.set_search_skip_below(1e-300);
  RecedingHorizonPlanner light(task_, p, &pool_, 0), plain(task_, SmallSearch(), &pool_, 0);
  EXPECT_EQ(Drive(&light, 60), Drive(&plain, 60));
  EXPECT_EQ(light.totals().light_replans, 0);
  EXPECT_EQ(light.totals().rollouts, plain.totals().rollouts);
  EXPECT_EQ(light.totals().rollout_steps, plain.totals().rollout_steps);
}

TEST_F(RecedingHorizonTest, TheSameSeedGivesTheSameActionsAndAnotherSeedOthers) {
  RecedingHorizonPlanner a(task_, SmallSearch(1), &pool_, 0), b(task_, SmallSearch(1), &pool_, 0),
      c(task_, SmallSearch(2), &pool_, 0);
  const std::vector<float> first = Drive(&a, 40);
  EXPECT_EQ(Drive(&b, 40), first);
  EXPECT_NE(Drive(&c, 40), first);
}

TEST_F(RecedingHorizonTest, TheActionsDoNotDependOnThePoolsThreads) {
  RolloutPool one(spec_, 1);
  RecedingHorizonPlanner a(task_, SmallSearch(), &pool_, 0), b(task_, SmallSearch(), &one, 0);
  EXPECT_EQ(Drive(&a, 30), Drive(&b, 30));
}

TEST_F(RecedingHorizonTest, AShiftedPlanActsExactlyAsTheOriginalAtTheSameStates) {
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  std::vector<double> theta(task_->dim());
  for (size_t i = 0; i < theta.size(); ++i) theta[i] = std::sin(1.7 * i);
  const int knot = task_->settings().knot_steps;
  const std::vector<double> shifted = task_->Shift(theta, 2 * knot, 0);
  // Up to the old plan's last knot, step s of the old plan is step s − 2·knot of the shifted one.
  for (int s = 2 * knot; s <= (task_->knots() - 1) * knot; ++s) {
    float a[2], b[2];
    task_->Action(*env, theta.data(), {s, 0}, nullptr, a);
    task_->Action(*env, shifted.data(), {s - 2 * knot, 0}, nullptr, b);
    EXPECT_EQ(a[0], b[0]) << "step " << s;
    EXPECT_EQ(a[1], b[1]) << "step " << s;
  }
}

TEST_F(RecedingHorizonTest, ARePlansIncumbentIsThePreviousPlanShiftedToNow) {
  config::PlannerConfig p = SmallSearch();
  RecedingHorizonPlanner planner(task_, p, &pool_, 0);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  ASSERT_TRUE(planner.Act(*env, a).ok());
  const std::vector<double> plan = planner.plan();
  for (int t = 0; t < p.replan_every(); ++t) {
    env->Step(a, walk_);
    ASSERT_TRUE(planner.Act(*env, a).ok());
  }
  ASSERT_EQ(planner.last_replan().env_step, p.replan_every());
  // The grid knot moved from step 0 to step 5: the plan shifted by one knot.
  const absl::StatusOr<double> shifted_cost = planner.Evaluate(*env, task_->Shift(plan, 5, 0));
  ASSERT_TRUE(shifted_cost.ok());
  EXPECT_EQ(planner.last_replan().incumbent_cost, *shifted_cost);
}

TEST_F(RecedingHorizonTest, ARescueRunsOnlyAboveItsThresholdAndNeverRaisesTheCost) {
  config::PlannerConfig p = SmallSearch();
  p.mutable_rescue()->set_cost_above(1e9);
  RecedingHorizonPlanner never(task_, p, &pool_, 0);
  Drive(&never, 20);
  EXPECT_EQ(never.totals().rescues, 0);
  // Every first re-plan from rest costs more than 0.5 (the target is 0.36 m away).
  p.mutable_rescue()->set_cost_above(0.5);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  RecedingHorizonPlanner rescued(task_, p, &pool_, 0);
  RecedingHorizonPlanner plain(task_, SmallSearch(), &pool_, 0);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  ASSERT_TRUE(rescued.Act(*env, a).ok());
  ASSERT_TRUE(plain.Act(*env, a).ok());
  EXPECT_TRUE(rescued.last_replan().rescued);
  EXPECT_EQ(rescued.totals().rescues, 1);
  EXPECT_GT(plain.last_replan().best_cost, 0.5);
  EXPECT_LE(rescued.last_replan().best_cost, plain.last_replan().best_cost);
  EXPECT_EQ(rescued.last_replan().incumbent_cost, plain.last_replan().incumbent_cost);
  // The rescue's two seeds (the regular search's best and the warm start) were simulated by
  // that search: read, not simulated again.
  EXPECT_EQ(rescued.totals().rollouts, rescued.last_replan().evaluations - 2);
}

TEST_F(RecedingHorizonTest, ARescueStopsAtTheFirstIterationBelowItsStopCost) {
  // From rest every first re-plan is in trouble (above 0.5); the rescue may run 8 iterations.
  config::PlannerConfig p = SmallSearch();
  p.mutable_rescue()->set_cost_above(0.5);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(8);
  RecedingHorizonPlanner full(task_, p, &pool_, 0);
  RecedingHorizonPlanner plain(task_, SmallSearch(), &pool_, 0);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  ASSERT_TRUE(full.Act(*env, a).ok());
  ASSERT_TRUE(plain.Act(*env, a).ok());
  const int regular = plain.last_replan().evaluations;
  const int all_iterations = full.last_replan().evaluations;
  ASSERT_GT(all_iterations, regular + 16 * 7);  // later iterations reuse carried elites
  // Its first iteration holds the regular search's best (a seed): with the stop cost at that
  // cost, the rescue ends after one iteration; with the stop cost below every cost, it runs all.
  p.mutable_rescue()->set_stop_below(plain.last_replan().best_cost);
  RecedingHorizonPlanner stopped(task_, p, &pool_, 0);
  ASSERT_TRUE(stopped.Act(*env, a).ok());
  EXPECT_TRUE(stopped.last_replan().rescued);
  EXPECT_EQ(stopped.last_replan().evaluations, regular + 16);
  EXPECT_LE(stopped.last_replan().best_cost, plain.last_replan().best_cost);
  p.mutable_rescue()->set_stop_below(1e-12);
  RecedingHorizonPlanner unreachable(task_, p, &pool_, 0);
  ASSERT_TRUE(unreachable.Act(*env, a).ok());
  EXPECT_EQ(unreachable.last_replan().evaluations, all_iterations);
}

TEST_F(RecedingHorizonTest, AModelBasedRescueSpendsItsBudgetAndLowersTheTroubledCost) {
  config::PlannerConfig p = SmallSearch();
  p.mutable_rescue()->set_cost_above(0.5);
  p.mutable_rescue()->mutable_bayes()->set_evaluations(20);
  p.mutable_rescue()->mutable_bayes()->set_initial(4);
  p.mutable_rescue()->mutable_bayes()->set_batch(4);
  RecedingHorizonPlanner bayes(task_, p, &pool_, 0);
  RecedingHorizonPlanner plain(task_, SmallSearch(), &pool_, 0);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  float a[2];
  ASSERT_TRUE(bayes.Act(*env, a).ok());
  ASSERT_TRUE(plain.Act(*env, a).ok());
  EXPECT_TRUE(bayes.last_replan().rescued);
  EXPECT_EQ(bayes.last_replan().evaluations, plain.last_replan().evaluations + 20);
  EXPECT_LT(bayes.last_replan().best_cost, plain.last_replan().best_cost);
  // Stopped once out of trouble: with the bar at the regular search's best, the first batch
  // (which holds that plan) ends it.
  p.mutable_rescue()->set_stop_below(plain.last_replan().best_cost);
  RecedingHorizonPlanner stopped(task_, p, &pool_, 0);
  ASSERT_TRUE(stopped.Act(*env, a).ok());
  EXPECT_LT(stopped.last_replan().evaluations, plain.last_replan().evaluations + 20);
  // The same seed, the same actions on 1 and 2 threads, over a drive with rescues.
  RolloutPool one(spec_, 1);
  RecedingHorizonPlanner two_threads(task_, p, &pool_, 0), one_thread(task_, p, &one, 0);
  EXPECT_EQ(Drive(&two_threads, 20), Drive(&one_thread, 20));
  EXPECT_GT(one_thread.totals().rescues, 0);
}

TEST_F(RecedingHorizonTest, APatientRescueWaitsForThatManyTroubledRePlansInARow) {
  config::PlannerConfig p = SmallSearch();
  p.mutable_rescue()->set_cost_above(0.5);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  // Re-plan by re-plan: was the regular search in trouble, did the rescue run.
  auto trace = [&](int patience) {
    p.mutable_rescue()->set_patience(patience);
    RecedingHorizonPlanner planner(task_, p, &pool_, 0);
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
    env->Reset(walk_);
    std::vector<std::pair<bool, bool>> replans;
    float a[2];
    for (int t = 0; t < 40; ++t) {
      const int before = planner.totals().replans;
      EXPECT_TRUE(planner.Act(*env, a).ok());
      if (planner.totals().replans > before) {
        const ReplanReport& r = planner.last_replan();
        const bool troubled = r.rescued || r.best_cost > 0.5;
        replans.push_back({troubled, r.rescued});
      }
      env->Step(a, walk_);
    }
    return replans;
  };
  const std::vector<std::pair<bool, bool>> at_once = trace(1);
  ASSERT_TRUE(at_once[0].second);  // from rest the first re-plan is in trouble
  const std::vector<std::pair<bool, bool>> never = trace(1000);
  ASSERT_TRUE(never[0].first);
  for (const auto& [troubled, rescued] : never) EXPECT_FALSE(rescued);
  // Patience 2: a rescue exactly at the second troubled re-plan in a row, then the count
  // starts again.
  const std::vector<std::pair<bool, bool>> patient = trace(2);
  EXPECT_FALSE(patient[0].second);
  int run = 0, rescues = 0;
  for (const auto& [troubled, rescued] : patient) {
    run = troubled ? run + 1 : 0;
    EXPECT_EQ(rescued, run == 2) << "troubled re-plans in a row: " << run;
    if (rescued) {
      ++rescues;
      run = 0;
    }
  }
  EXPECT_GT(rescues, 0) << "the point mass stays in trouble for two re-plans from rest";
}

// A constant prior action: the plan's offsets are added to it.
class ConstantPrior final : public ActionPrior {
 public:
  void Write(const Env&, double* prior) const override {
    prior[0] = 0.25;
    prior[1] = -0.5;
  }
};

TEST_F(RecedingHorizonTest, APriorActionIsAddedUnderThePlan) {
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  const std::vector<double> zero(task_->dim(), 0.0);
  const ConstantPrior prior;
  float a[2];
  task_->Action(*env, zero.data(), {0, 0}, nullptr, a);
  EXPECT_EQ(a[0], 0.0f);
  double p[2];
  prior.Write(*env, p);
  task_->Action(*env, zero.data(), {0, 0}, p, a);
  EXPECT_EQ(a[0], 0.25f);
  EXPECT_EQ(a[1], -0.5f);
  // The planner with the prior predicts what it executes.
  RecedingHorizonPlanner planner(task_, SmallSearch(), &pool_, 0, &prior);
  Drive(&planner, 20);
  EXPECT_GT(planner.totals().prediction_checks, 10);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
}

TEST_F(RecedingHorizonTest, APolicyPriorIsThePolicysMeanActionZeroWithoutOneAndRefusesOtherSizes) {
  PolicyPrior prior(*spec_);
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  env->Reset(walk_);
  double p[2] = {7, 7};
  prior.Write(*env, p);
  EXPECT_EQ(p[0], 0.0);
  EXPECT_EQ(p[1], 0.0);
  auto policy = std::make_shared<const EigenPolicy>(::juggle::testing::ConstantPolicy(4, 2, 0.5f));
  ASSERT_TRUE(prior.Set(policy).ok());
  prior.Write(*env, p);
  EXPECT_FLOAT_EQ(p[0], std::tanh(0.5f));
  EXPECT_FLOAT_EQ(p[1], std::tanh(0.5f));
  // The planner acting on it predicts exactly what it executes.
  RecedingHorizonPlanner planner(task_, SmallSearch(), &pool_, 0, &prior);
  Drive(&planner, 20);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  auto wrong = std::make_shared<const EigenPolicy>(::juggle::testing::ConstantPolicy(4, 3, 0.5f));
  const absl::Status refused = prior.Set(wrong);
  EXPECT_EQ(refused.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(refused.message()),
              HasSubstr("writes 3 actions, but the planner's point_mass envs have 4 and 2"));
  EXPECT_TRUE(prior.has_policy()) << "a refused policy leaves the last one";
}

TEST_F(RecedingHorizonTest, TheProposalAloneIsACandidateOfEveryReplanOnceAPolicyIsSet) {
  PolicyPrior prior(*spec_);
  {
    RecedingHorizonPlanner planner(task_, SmallSearch(), &pool_, 0, &prior);
    Drive(&planner, 20);
    EXPECT_EQ(planner.totals().proposal_tried, 0) << "no policy, nothing proposed";
  }
  auto policy = std::make_shared<const EigenPolicy>(::juggle::testing::ConstantPolicy(4, 2, 0.5f));
  ASSERT_TRUE(prior.Set(policy).ok());
  RecedingHorizonPlanner planner(task_, SmallSearch(), &pool_, 0, &prior);
  Drive(&planner, 20);
  EXPECT_EQ(planner.totals().replans, 4);
  EXPECT_EQ(planner.totals().proposal_tried, 4);
  EXPECT_LE(planner.totals().proposal_chosen, 4);
  // At rest on the target under a zero policy, zero offsets cost nothing and anything else
  // costs more: every re-plan chooses the proposal alone.
  PointMassTaskSettings at_rest;
  at_rest.target[0] = at_rest.target[1] = 0;
  auto zero = std::make_shared<const EigenPolicy>(::juggle::testing::ConstantPolicy(4, 2, 0.0f));
  ASSERT_TRUE(prior.Set(zero).ok());
  RecedingHorizonPlanner resting(std::make_shared<PointMassTask>(at_rest), SmallSearch(), &pool_,
                                 0, &prior);
  Drive(&resting, 20);
  EXPECT_EQ(resting.totals().proposal_tried, 4);
  EXPECT_EQ(resting.totals().proposal_chosen, 4);
}

TEST(PlanningTasksTest, AFamilyWithoutATaskIsAnErrorNamingTheFamiliesThatHaveOne) {
  const absl::StatusOr<std::shared_ptr<const PlanningTask>> task =
      MakePlanningTask(PointMassSpec::Create(), config::PlannerConfig());
  EXPECT_EQ(task.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(task.status().message()),
              HasSubstr("no task for the point_mass family; families with a planning task: "
                        "soccer_juggle"));
}

}  // namespace
}  // namespace juggle::planner
