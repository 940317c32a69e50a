// The planner controller in the evaluation loop: each episode gets its own planner whatever
// the batch does (the runner compacts finished episodes away), so an episode's result does not
// depend on which other episodes run beside it.
#include "planner/planner_controller.h"

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::planner {
namespace {

TEST(PlannerControllerTest, AnEnvKeepsItsPlannerWhenTheBatchIsCompacted) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/right_foot_planner.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  config::PlannerConfig& p = *config->run.mutable_planner();
  p.set_samples(8);
  p.set_iterations(2);
  p.set_horizon_steps(24);
  p.set_replan_every(3);
  p.set_body_knot_steps(0);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  const AdaptiveWalk walk(&(*spec)->graph());
  const int act = (*spec)->act_dim();
  // Env b's actions over 12 steps: in a batch [a, b] throughout, and in one that drops a after
  // 6 steps (b moves to the front, as the episode runner compacts finished episodes away).
  std::vector<std::vector<float>> b_actions;
  for (bool drop_a : {false, true}) {
    absl::StatusOr<std::unique_ptr<PlannerController>> controller =
        PlannerController::Create(*spec, *config);
    ASSERT_TRUE(controller.ok()) << controller.status();
    std::unique_ptr<Env> a = (*spec)->NewEnv(Rng::ForStream(1000000, 0, 0));
    std::unique_ptr<Env> b = (*spec)->NewEnv(Rng::ForStream(1000000, 0, 1));
    a->Reset(walk);
    b->Reset(walk);
    std::vector<float> actions(2 * act), seen;
    for (int t = 0; t < 12; ++t) {
      const bool with_a = !(drop_a && t >= 6);
      const Env* batch[2] = {with_a ? a.get() : b.get(), b.get()};
      const int n = with_a ? 2 : 1;
      (*controller)->Act(batch, nullptr, n, actions.data());
      const float* for_b = actions.data() + (n - 1) * act;
      seen.insert(seen.end(), for_b, for_b + act);
      if (with_a) a->Step(actions.data(), walk);
      b->Step(for_b, walk);
    }
    b_actions.push_back(seen);
    EXPECT_EQ((*controller)->totals().prediction_mismatches, 0);
  }
  EXPECT_EQ(b_actions[0], b_actions[1]);
}

TEST(PlannerControllerTest, AnEpisodeRunAloneWithItsIndexAsStreamBasePlansAsInItsBatch) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/right_foot_planner.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  config::PlannerConfig& p = *config->run.mutable_planner();
  p.set_samples(8);
  p.set_iterations(2);
  p.set_horizon_steps(24);
  p.set_replan_every(3);
  p.set_body_knot_steps(0);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  const AdaptiveWalk walk(&(*spec)->graph());
  const int act = (*spec)->act_dim();
  // Episode 1's actions over 9 steps: in the batch [0, 1] (stream base 0), then alone as
  // `juggle eval --first-episode=1 --episodes=1` runs it (stream base 1), then alone from
  // stream base 0 (the old behaviour), which must differ for the test to mean anything.
  std::vector<std::vector<float>> runs;
  for (auto [with_episode_0, base] : {std::pair{true, 0}, std::pair{false, 1}, std::pair{false, 0}}) {
    absl::StatusOr<std::unique_ptr<PlannerController>> controller =
        PlannerController::Create(*spec, *config, base);
    ASSERT_TRUE(controller.ok()) << controller.status();
    std::unique_ptr<Env> e0 = (*spec)->NewEnv(Rng::ForStream(1000000, 0, 0));
    std::unique_ptr<Env> e1 = (*spec)->NewEnv(Rng::ForStream(1000000, 0, 1));
    e0->Reset(walk);
    e1->Reset(walk);
    std::vector<float> actions(2 * act), seen;
    for (int t = 0; t < 9; ++t) {
      const Env* batch[2] = {with_episode_0 ? e0.get() : e1.get(), e1.get()};
      const int n = with_episode_0 ? 2 : 1;
      (*controller)->Act(batch, nullptr, n, actions.data());
      const float* for_e1 = actions.data() + (n - 1) * act;
      seen.insert(seen.end(), for_e1, for_e1 + act);
      if (with_episode_0) e0->Step(actions.data(), walk);
      e1->Step(for_e1, walk);
    }
    runs.push_back(seen);
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_NE(runs[0], runs[2]);
}

}  // namespace
}  // namespace juggle::planner
