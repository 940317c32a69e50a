// The planner controller in the evaluation loop: each episode gets its own planner whatever
// the batch does (the runner compacts finished episodes away), so an episode's result does not
// depend on which other episodes run beside it; and an episode run alone with its index as the
// stream base plans as it did in its batch.
#include "planner/planner_controller.h"

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::planner {
namespace {

class PlannerControllerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(::juggle::testing::RepoPath("configs/right_foot_planner.textproto"));
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    config::PlannerConfig& p = *config_.run.mutable_planner();
    p.set_samples(8);
    p.set_iterations(2);
    p.set_horizon_steps(24);
    p.set_replan_every(3);
    p.set_body_knot_steps(0);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }

  // Episode 1's actions over `steps` steps under a new controller with `stream_base`, episode 0
  // (held-out stream 0) batched in front of it for its first `with_episode_0` steps.
  std::vector<float> EpisodeOneActions(uint64_t stream_base, int with_episode_0, int steps) {
    absl::StatusOr<std::unique_ptr<PlannerController>> controller =
        PlannerController::Create(spec_, config_, stream_base);
    EXPECT_TRUE(controller.ok()) << controller.status();
    if (!controller.ok()) return {};
    const int act = spec_->act_dim();
    std::unique_ptr<Env> e0 = spec_->NewEnv(Rng::ForStream(1000000, 0, 0));
    std::unique_ptr<Env> e1 = spec_->NewEnv(Rng::ForStream(1000000, 0, 1));
    e0->Reset(*walk_);
    e1->Reset(*walk_);
    std::vector<float> actions(2 * act), seen;
    for (int t = 0; t < steps; ++t) {
      const bool with_e0 = t < with_episode_0;
      const Env* batch[2] = {with_e0 ? e0.get() : e1.get(), e1.get()};
      const int n = with_e0 ? 2 : 1;
      (*controller)->Act(batch, nullptr, n, actions.data());
      const float* for_e1 = actions.data() + (n - 1) * act;
      seen.insert(seen.end(), for_e1, for_e1 + act);
      if (with_e0) e0->Step(actions.data(), *walk_);
      e1->Step(for_e1, *walk_);
    }
    EXPECT_EQ((*controller)->totals().prediction_mismatches, 0);
    return seen;
  }

  LoadedConfig config_;
  std::shared_ptr<const EnvSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(PlannerControllerTest, AnEnvKeepsItsPlannerWhenTheBatchIsCompacted) {
  // In a batch [0, 1] throughout, and in one that drops episode 0 after 6 steps (1 moves to
  // the front, as the episode runner compacts finished episodes away).
  EXPECT_EQ(EpisodeOneActions(0, 12, 12), EpisodeOneActions(0, 6, 12));
}

TEST_F(PlannerControllerTest, AnEpisodeRunAloneWithItsIndexAsStreamBasePlansAsInItsBatch) {
  // In the batch [0, 1], and alone as `juggle eval --first-episode=1 --episodes=1` runs it
  // (stream base 1); alone from stream base 0 (the old behaviour) it differs, so the
  // comparison means something.
  const std::vector<float> batch = EpisodeOneActions(0, 9, 9);
  EXPECT_EQ(batch, EpisodeOneActions(1, 0, 9));
  EXPECT_NE(batch, EpisodeOneActions(0, 0, 9));
}

}  // namespace
}  // namespace juggle::planner
