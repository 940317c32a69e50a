// The planner's around-the-world term (PlannerCost.around_the_world, docs/planner.md
// "Around-the-world"): over a rollout it is the weight times the env's violation summed over the
// steps, divided by the horizon, and it is part of the total.
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "common/adaptive_walk.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/soccer_juggle/cost.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

TEST(AroundTheWorldCostTest, TheTermIsTheWeightTimesTheStepsViolationsOverTheHorizon) {
  absl::StatusOr<LoadedConfig> config = ::juggle::testing::LoadRightFootPlannerWithGraph(
      ::juggle::testing::ReadRepoFile("configs/graphs/foot_and_atw.textproto"),
      "soccer_juggle { cost { around_the_world: 50 } }");
  ASSERT_TRUE(config.ok()) << config.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> base = CreateEnvSpec(*config);
  ASSERT_TRUE(base.ok()) << base.status();
  auto spec = std::dynamic_pointer_cast<const JuggleSpec>(*base);
  const config::PlannerCost& cost = config->run.planner().soccer_juggle().cost();
  ASSERT_EQ(cost.around_the_world(), 50);
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(2));
  env.ResetAt(*spec->graph().FindNode("right_atw_down"), walk);
  constexpr int kHorizon = 12;
  SoccerRolloutScorer scorer(cost, kHorizon, /*run_on_every_kick=*/false);
  config::PlannerCost without = cost;
  without.set_around_the_world(0);
  SoccerRolloutScorer plain(without, kHorizon, false);
  scorer.Begin(env);
  plain.Begin(env);
  const float zero[kNumActions] = {0};
  double sum = 0;
  for (int t = 0; t < kHorizon; ++t) {
    const StepResult r = env.Step(zero, walk);
    ASSERT_FALSE(r.terminated()) << "step " << t;
    scorer.AfterStep(env, zero, r);
    plain.AfterStep(env, zero, r);
    sum += env.AroundTheWorldViolation();  // the env's violation at each state, independently
  }
  const double total = scorer.Finish(env);
  const double plain_total = plain.Finish(env);
  ASSERT_GT(sum, 0.0) << "zero action strays from the circle's angle";
  const std::vector<std::string> names = SoccerTermNames();
  ASSERT_EQ(names.back(), "around_the_world");
  const std::vector<double> terms = scorer.terms();
  ASSERT_EQ(terms.size(), names.size());
  EXPECT_NEAR(terms.back(), 50 * sum / kHorizon, 1e-12 * sum);
  EXPECT_EQ(plain.terms().back(), 0.0);
  EXPECT_NEAR(total - plain_total, 50 * sum / kHorizon, 1e-9 * total);
  EXPECT_NEAR(std::accumulate(terms.begin(), terms.end(), 0.0), total, 1e-9 * total);
}

}  // namespace
}  // namespace juggle::planner
