// The in-loop env with the base controllers (configs/toss_residual_*.textproto): no partner
// policies needed, residual actions, transition runs and the failure bookkeeping that weights
// patterns. Its snapshots are tested with the other envs' in envs/env_snapshot_test.cc.
#include <memory>
#include <vector>

#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/loop_env.h"
#include "envs/toss/outcomes.h"

namespace juggle::toss {
namespace {

std::shared_ptr<const TossSpec> ResidualSpec(const std::string& task,
                                             void (*edit)(config::TossConfig*) = nullptr) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/toss_residual_" + task + ".textproto"));
  EXPECT_TRUE(config.ok()) << config.status();
  if (edit) edit(config->run.mutable_toss());
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return *spec;
}

TEST(ResidualLoopTest, ZeroResidualThrowsAreGoodAndNoRunFails) {
  auto spec = ResidualSpec("throw");
  TossLoopEnv env(spec, Rng::ForStream(1, 0, 0));
  const AdaptiveWalk walk(&spec->graph());
  const float zero[kTossJoints] = {0, 0, 0, 0};
  int releases = 0, good = 0;
  for (int episode = 0; episode < 40; ++episode) {
    env.Reset(walk);
    for (int k = 0; k < 200; ++k) {
      const StepResult r = env.Step(zero, walk);
      if (r.outcome == Outcome::kRunning) continue;
      releases += r.outcome == kReleased;
      good += env.completions();
      break;
    }
  }
  EXPECT_EQ(releases, 40);
  EXPECT_EQ(good, 40);
  for (double rate : env.failure_rates()) EXPECT_EQ(rate, 0.0);
}

TEST(ResidualLoopTest, RunsThatDropAreCountedAgainstTheirPattern) {
  auto spec = ResidualSpec("throw", [](config::TossConfig* t) {
    t->mutable_base()->set_residual_scale(1.0);
  });
  TossLoopEnv env(spec, Rng::ForStream(2, 0, 0));
  const AdaptiveWalk walk(&spec->graph());
  const float wild[kTossJoints] = {1, 1, -1, 1};  // 1 rad off on every joint: wild throws
  for (int episode = 0; episode < 30; ++episode) {
    env.Reset(walk);
    while (env.Step(wild, walk).outcome == Outcome::kRunning) {
    }
  }
  // Every run but the current one failed; each failure adds 0.1 × (1 − rate) to its pattern.
  EXPECT_GT(env.runs_started(), 5);
  double total = 0;
  for (double rate : env.failure_rates()) total += rate;
  EXPECT_GT(total, 0.09 * (env.runs_started() - 1));
}

TEST(ResidualLoopTest, TransitionFractionOneMakesEveryRunATransition) {
  auto spec = ResidualSpec("catch", [](config::TossConfig* t) {
    t->mutable_loop()->set_transition_fraction(1.0);
  });
  TossLoopEnv env(spec, Rng::ForStream(3, 0, 0));
  EXPECT_NE(env.juggler().schedule().Name().find('>'), std::string::npos)
      << env.juggler().schedule().Name();
}

}  // namespace
}  // namespace juggle::toss
