// The toss runtime on the live page (configs/toss_base.textproto, base controllers): a pattern
// chosen mid-run is juggled through the passage without a drop; invalid patterns and patterns
// with more balls than the model are refused with their reason; the wind is set and bounded; a
// poke lands on the highest ball in flight as Δv = J/m along the ball's two slide joints.
#include "play/siteswap_world.h"

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::play {
namespace {

using ::testing::HasSubstr;

std::unique_ptr<SiteswapWorld> MakeWorld(const std::string& pattern) {
  absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig("toss_base");
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  absl::StatusOr<std::unique_ptr<SiteswapWorld>> world =
      SiteswapWorld::Create(*spec, pattern, /*run_seed=*/1);
  EXPECT_TRUE(world.ok()) << world.status();
  return world.ok() ? *std::move(world) : nullptr;
}

TEST(SiteswapWorldTest, APatternChosenMidRunIsJuggledThroughThePassageWithoutADrop) {
  std::unique_ptr<SiteswapWorld> world = MakeWorld("3");
  ASSERT_NE(world, nullptr);
  for (int i = 0; i < 300; ++i) ASSERT_TRUE(world->Step()) << "step " << i;
  ASSERT_TRUE(world->Choose("531").ok());
  int steps = 0;
  while (steps < 1500 && world->Step()) ++steps;
  nlohmann::json status;
  world->AppendStatus(&status);
  EXPECT_EQ(steps, 1500) << status.dump();
  EXPECT_EQ(status["pattern"], "531");
  EXPECT_EQ(status["schedule"], "3>531");
  EXPECT_GT(status["throws"].get<int>(), 40);
  ASSERT_TRUE(world->Choose("3").ok());
  steps = 0;
  while (steps < 1000 && world->Step()) ++steps;
  world->AppendStatus(&status);
  EXPECT_EQ(steps, 1000) << status.dump();
  EXPECT_EQ(status["schedule"], "3>531>3");
}

TEST(SiteswapWorldTest, RefusesInvalidPatternsAndMoreBallsThanTheModelHas) {
  std::unique_ptr<SiteswapWorld> world = MakeWorld("3");
  ASSERT_NE(world, nullptr);
  absl::Status invalid = world->Choose("543");
  EXPECT_EQ(invalid.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(invalid.message(), HasSubstr("invalid"));
  absl::Status nine = world->Choose("9");
  EXPECT_EQ(nine.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(nine.message(), HasSubstr("9 balls"));
  nlohmann::json status;
  world->AppendStatus(&status);
  EXPECT_EQ(status["pattern"], "3");  // nothing changed
  absl::StatusOr<std::unique_ptr<SiteswapWorld>> soccer =
      SiteswapWorld::Create(testing::LoadSpec("right_foot_planner"), "3", 1);
  EXPECT_THAT(soccer.status().message(), HasSubstr("needs a toss config"));
}

TEST(SiteswapWorldTest, SetsTheWindWithinItsBoundAndPokesTheHighestBallInFlight) {
  std::unique_ptr<SiteswapWorld> world = MakeWorld("3");
  ASSERT_NE(world, nullptr);
  ASSERT_TRUE(world->SetWind(0.5).ok());
  EXPECT_DOUBLE_EQ(world->juggler().world().wind(), 0.5);
  EXPECT_EQ(world->SetWind(3).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_DOUBLE_EQ(world->juggler().world().wind(), 0.5);
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(world->Step());
  const toss::TossWorld& w = world->juggler().world();
  int ball = -1;
  for (int b = 0; b < toss::kTossBalls; ++b) {
    if (w.mode(b) == toss::BallMode::kFree &&
        (ball < 0 || w.ball_position(b).z > w.ball_position(ball).z)) {
      ball = b;
    }
  }
  ASSERT_GE(ball, 0);
  const toss::Vec2 before = w.ball_velocity(ball);
  ASSERT_TRUE(world->Poke({0.02, 0.5, 0.04}).ok());  // y: out of the plane, no joint takes it
  const mjModel* m = world->model();
  const double mass = m->body_mass[m->dof_bodyid[w.spec().ball(ball).dof_x]];
  EXPECT_NEAR(w.ball_velocity(ball).x - before.x, 0.02 / mass, 1e-9);
  EXPECT_NEAR(w.ball_velocity(ball).z - before.z, 0.04 / mass, 1e-9);
}

}  // namespace
}  // namespace juggle::play
