// Toss juggling (docs/toss.md): the home pose, the auto-catch and auto-release mechanics, the
// catch and throw tasks' rewards and episode rules, and mirroring of the right arm's policy
// onto the left arm.
#include <algorithm>
#include <cmath>
#include <functional>

#include "envs/toss/outcomes.h"
#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/task_env.h"
#include "envs/toss/spec.h"
#include "envs/toss/world.h"

namespace juggle::toss {
namespace {

std::shared_ptr<const TossSpec> LoadTossSpec(
    config::TossTask task, const std::function<void(config::TossConfig*)>& edit = nullptr) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/toss_catch.textproto"));
  EXPECT_TRUE(config.ok()) << config.status();
  if (!config.ok()) return nullptr;
  config->run.mutable_toss()->set_task(task);
  if (edit) edit(config->run.mutable_toss());
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

const AdaptiveWalk& NoWalk() {
  static const ControlGraph* graph = new ControlGraph();
  static const AdaptiveWalk* walk = new AdaptiveWalk(graph);
  return *walk;
}

TEST(TossSpecTest, HomePosePutsBothPalmsAtTheMirroredHomePoint) {
  auto spec = LoadTossSpec(config::CATCH);
  ASSERT_NE(spec, nullptr);
  TossWorld world(spec);
  const Vec2 right = world.palm_position(Hand::kRight), left = world.palm_position(Hand::kLeft);
  EXPECT_NEAR(right.x, -0.2, 1e-9);
  EXPECT_NEAR(right.z, 0.95, 1e-9);
  EXPECT_NEAR(left.x, 0.2, 1e-9);
  EXPECT_NEAR(left.z, 0.95, 1e-9);
  EXPECT_EQ(spec->obs_dim(), kTossCatchObs);
  EXPECT_EQ(spec->act_dim(), kTossJoints);
}

TEST(TossSpecTest, UnreachableHomePointIsAnErrorNamingTheField) {
  absl::StatusOr<LoadedConfig> config =
      ParseRunConfig("toss {\n  task: CATCH\n  hand_z: 2.5\n}\n", testing::RepoPath("configs/x.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(*config);
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(spec.status().message().find("x.textproto:"), std::string::npos) << spec.status();
  EXPECT_NE(spec.status().message().find("out of the arm's reach"), std::string::npos);
}

class TossWorldTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = LoadTossSpec(config::CATCH);
    ASSERT_NE(spec_, nullptr);
    world_ = std::make_unique<TossWorld>(spec_);
  }
  std::shared_ptr<const TossSpec> spec_;
  std::unique_ptr<TossWorld> world_;
};

TEST_F(TossWorldTest, CatchNeedsAFreeDescendingBallWithinTheRadiusAndAnEmptyHand) {
  const Vec2 palm = world_->palm_position(Hand::kRight);
  world_->SetFree(0, {palm.x, palm.z + 0.05}, {0, -1});
  EXPECT_TRUE(world_->CanCatch(0, Hand::kRight));
  EXPECT_FALSE(world_->CanCatch(0, Hand::kLeft));  // 0.4 m away
  world_->SetFree(0, {palm.x, palm.z + 0.05}, {0, +1});
  EXPECT_FALSE(world_->CanCatch(0, Hand::kRight)) << "a rising ball is not caught";
  world_->SetFree(0, {palm.x + 0.08, palm.z}, {0, -1});
  EXPECT_FALSE(world_->CanCatch(0, Hand::kRight)) << "0.08 m is beyond the 0.07 m radius";
  world_->SetFree(0, {palm.x, palm.z + 0.05}, {0, -1});
  world_->Hold(1, Hand::kRight);
  EXPECT_FALSE(world_->CanCatch(0, Hand::kRight)) << "the hand is full";
}

TEST_F(TossWorldTest, HeldBallFollowsThePalmAndLeavesWithThePalmVelocity) {
  world_->Hold(0, Hand::kRight);
  const float up[kTossJoints] = {0, -0.6f, 0.3f, 0};
  for (int i = 0; i < 8; ++i) {
    world_->SetAction(Hand::kRight, up);
    world_->Step();
    const Vec2 palm = world_->palm_position(Hand::kRight), ball = world_->ball_position(0);
    ASSERT_NEAR(ball.x, palm.x, 1e-12);
    ASSERT_NEAR(ball.z, palm.z, 1e-12);
  }
  const Vec2 palm_v = world_->palm_velocity(Hand::kRight);
  ASSERT_GT(std::hypot(palm_v.x, palm_v.z), 0.5) << "the arm should be moving";
  const Vec2 p0 = world_->ball_position(0);
  const Vec2 v = world_->Release(0);
  EXPECT_DOUBLE_EQ(v.x, palm_v.x);
  EXPECT_DOUBLE_EQ(v.z, palm_v.z);
  EXPECT_EQ(world_->mode(0), BallMode::kFree);
  // Free flight from here: MuJoCo's semi-implicit Euler, cross-checked in closed form.
  const int n = 20;
  const double h = spec_->dt(), g = 9.81;
  for (int i = 0; i < n; ++i) world_->Step();
  const Vec2 p = world_->ball_position(0);
  EXPECT_NEAR(p.x, p0.x + v.x * n * h, 1e-9);
  EXPECT_NEAR(p.z, p0.z + v.z * n * h - g * h * h * n * (n + 1) / 2, 1e-9);
}

TEST_F(TossWorldTest, WindPushesOnlyFreeBalls) {
  auto windy = LoadTossSpec(config::CATCH, [](config::TossConfig* t) { t->set_wind_force(0.26); });
  TossWorld world(windy);
  world.SetFree(0, {0, 2}, {0, 0});
  world.Hold(1, Hand::kRight);
  for (int i = 0; i < 10; ++i) world.Step();
  // a = F / m = 0.26 / 0.13 = 2 m/s²; after 10 steps of 10 ms the speed is 0.2 m/s.
  EXPECT_NEAR(world.ball_velocity(0).x, 0.2, 1e-9);
  EXPECT_NEAR(world.ball_position(1).x, world.palm_position(Hand::kRight).x, 1e-12);
}

TEST(TossEnvTest, UntouchedIncomingBallIsDroppedWithMinusW2AndTheEpisodeEnds) {
  // The ball lands 0.5 m outside the hand: a zero action cannot catch it.
  auto spec = LoadTossSpec(config::CATCH, [](config::TossConfig* t) {
    t->set_landing_spread(0);
    t->set_hand_x(-0.2);
  });
  TossTaskEnv env(spec, Rng(3));
  env.Reset(NoWalk());
  TossWorld* world = const_cast<TossWorld*>(&env.world());
  world->SetFree(0, {-0.7, 1.2}, {0, -1});
  const float zero[kTossJoints] = {0, 0, 0, 0};
  StepResult r;
  double effort_part = 0;
  int steps = 0;
  do {
    r = env.Step(zero, NoWalk());
    effort_part = -0.12 * env.world().Effort(Hand::kRight);
    ++steps;
  } while (r.outcome == Outcome::kRunning && steps < 200);
  EXPECT_EQ(r.outcome, kDropped);
  EXPECT_LT(env.world().ball_position(0).z, 0.55);
  EXPECT_NEAR(r.reward, effort_part - 1.0, 1e-5);
  EXPECT_EQ(env.completions(), 0);
}

TEST(TossEnvTest, BallDroppedIntoTheStillHandIsCaughtWithTheHeightPenalty) {
  auto spec = LoadTossSpec(config::CATCH, [](config::TossConfig* t) { t->set_start_noise(0); });
  TossTaskEnv env(spec, Rng(4));
  env.Reset(NoWalk());
  TossWorld* world = const_cast<TossWorld*>(&env.world());
  const Vec2 palm = world->palm_position(Hand::kRight);
  world->SetFree(0, {palm.x, palm.z + 0.3}, {0, 0});
  const float zero[kTossJoints] = {0, 0, 0, 0};
  StepResult r;
  for (int i = 0; i < 100 && r.outcome == Outcome::kRunning; ++i) r = env.Step(zero, NoWalk());
  ASSERT_EQ(r.outcome, kCaught);
  EXPECT_EQ(env.completions(), 1);
  EXPECT_EQ(env.world().mode(0), BallMode::kHeld);
  // Caught within the radius above the palm: the height error is at most 0.07 m.
  EXPECT_LE(r.reward, 0.0f);
  EXPECT_GT(r.reward, -0.07f - 0.12f * 1e-3f);
}

TEST(TossEnvTest, ThrowReleasesAtTheBeatWithTheRewardOfItsErrors) {
  auto spec = LoadTossSpec(config::THROW);
  TossTaskEnv env(spec, Rng(5));
  env.Reset(NoWalk());
  std::vector<float> obs(spec->obs_dim());
  env.WriteObservation(obs.data());
  const float t_throw = obs[kTossCatchObs];
  EXPECT_GE(t_throw, 0.35f - 0.08f - 0.006f);
  EXPECT_LE(t_throw, 0.35f + 0.08f + 0.006f);
  EXPECT_FLOAT_EQ(obs[kTossCatchObs + 2], static_cast<float>(env.target_velocity().z));
  const int expected_steps = static_cast<int>(std::lround(t_throw / 0.01));
  const float action[kTossJoints] = {0, -0.5f, 0.2f, 0};
  StepResult r;
  int steps = 0;
  double effort = 0;
  while (r.outcome == Outcome::kRunning) {
    r = env.Step(action, NoWalk());
    effort = env.world().Effort(Hand::kRight);
    ++steps;
  }
  EXPECT_EQ(r.outcome, kReleased);
  EXPECT_EQ(steps, expected_steps);
  EXPECT_EQ(env.world().mode(0), BallMode::kFree);
  const double dp = env.release_position_error(), dv = env.release_velocity_error();
  EXPECT_NEAR(r.reward, -0.29 * effort - 9.0 * dp * dp - 1.4 * dv * dv, 1e-4);
  // The velocity error is measured against Eq. 2: v̄_z = g·T_air/2.
  const double flight = FlightTimeEq1(env.throw_value(), spec->timing());
  EXPECT_NEAR(env.target_velocity().z, 9.81 * flight / 2, 1e-12);
}

TEST(TossEnvTest, PredictLandingMatchesTheClosedFormParabola) {
  // Thrown up at 3 m/s from 1 m: back at 1 m after 2·3/g.
  const BallisticLanding l = PredictLanding({0.1, 1.0}, {0.5, 3.0}, 1.0, 9.81);
  EXPECT_NEAR(l.time, 6.0 / 9.81, 1e-12);
  EXPECT_NEAR(l.x, 0.1 + 0.5 * 6.0 / 9.81, 1e-12);
  EXPECT_LT(PredictLanding({0, 0.5}, {0, 1.0}, 2.0, 9.81).time, 0) << "never reaches 2 m";
}

// The left arm running the right arm's policy through the mirror sees exactly what the right
// arm sees and earns the same rewards, while its body moves as the mirror image.
void ExpectMirrored(config::TossTask task) {
  auto spec = LoadTossSpec(task);
  ASSERT_NE(spec, nullptr);
  TossTaskEnv right(spec, Rng(11), Hand::kRight), left(spec, Rng(11), Hand::kLeft);
  right.Reset(NoWalk());
  left.Reset(NoWalk());
  std::vector<float> obs_r(spec->obs_dim()), obs_l(spec->obs_dim());
  Rng actions(99);
  for (int step = 0; step < 40; ++step) {
    right.WriteObservation(obs_r.data());
    left.WriteObservation(obs_l.data());
    for (int i = 0; i < spec->obs_dim(); ++i) {
      ASSERT_NEAR(obs_r[i], obs_l[i], 1e-5) << "step " << step << " obs " << i;
    }
    const Vec2 pr = right.world().palm_position(Hand::kRight);
    const Vec2 pl = left.world().palm_position(Hand::kLeft);
    ASSERT_NEAR(pr.x, -pl.x, 1e-9);
    ASSERT_NEAR(pr.z, pl.z, 1e-9);
    float a[kTossJoints];
    for (float& v : a) v = static_cast<float>(actions.Uniform(-0.5, 0.5));
    const StepResult rr = right.Step(a, NoWalk()), rl = left.Step(a, NoWalk());
    ASSERT_NEAR(rr.reward, rl.reward, 1e-5) << "step " << step;
    ASSERT_EQ(rr.outcome, rl.outcome) << "step " << step;
    if (rr.outcome != Outcome::kRunning) return;
  }
}

TEST(TossEnvTest, LeftArmThroughTheMirrorIsTheRightArmsMirrorImageInTheCatchTask) {
  ExpectMirrored(config::CATCH);
}

TEST(TossEnvTest, LeftArmThroughTheMirrorIsTheRightArmsMirrorImageInTheThrowTask) {
  ExpectMirrored(config::THROW);
}

TEST(TossEnvTest, SameSeedGivesTheSameEpisode) {
  auto spec = LoadTossSpec(config::CATCH);
  TossTaskEnv a(spec, Rng(21)), b(spec, Rng(21)), c(spec, Rng(22));
  a.Reset(NoWalk());
  b.Reset(NoWalk());
  c.Reset(NoWalk());
  std::vector<float> oa(spec->obs_dim()), ob(spec->obs_dim()), oc(spec->obs_dim());
  a.WriteObservation(oa.data());
  b.WriteObservation(ob.data());
  c.WriteObservation(oc.data());
  EXPECT_EQ(oa, ob);
  EXPECT_NE(oa, oc);
}

// A recorded start state is in the right arm's frame: the left arm starts at its mirror image;
// in the throw task the ball starts in the (off-home) palm.
TEST(TossEnvTest, RecordedStartStatePutsTheActingArmThereInItsOwnFrame) {
  const std::array<double, kTossJoints> angle{0.1, 1.2, -1.9, -0.4}, speed{0, 8, -10, -6};
  auto spec = LoadTossSpec(config::THROW, [&](config::TossConfig* t) {
    config::TossArmState* s = t->add_start_state();
    for (int j = 0; j < kTossJoints; ++j) {
      s->add_angle(angle[j]);
      s->add_speed(speed[j]);
    }
    t->set_recorded_start_fraction(1);
    t->set_recorded_start_noise(0);
  });
  ASSERT_NE(spec, nullptr);
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    TossTaskEnv env(spec, Rng(3), hand);
    env.Reset(NoWalk());
    const TossArmJoints& arm = spec->arm(hand);
    const double mirror = TossSpec::MirrorSign(hand);
    for (int j = 0; j < kTossJoints; ++j) {
      EXPECT_NEAR(env.data()->qpos[arm.qpos[j]], mirror * angle[j], 1e-12) << "joint " << j;
      EXPECT_NEAR(env.data()->qvel[arm.dof[j]], mirror * speed[j], 1e-12) << "joint " << j;
    }
    std::vector<float> obs(spec->obs_dim());
    env.WriteObservation(obs.data());
    EXPECT_GT(std::hypot(obs[0], obs[1]), 0.05) << "the palm starts away from home";
    EXPECT_FLOAT_EQ(obs[4], obs[0]) << "the ball starts in the palm";
    EXPECT_FLOAT_EQ(obs[5], obs[1]);
  }
}

// Start speeds come from start_speed_noise when it is set, from 10 × start_noise otherwise.
TEST(TossEnvTest, StartSpeedNoiseBoundsTheInitialJointSpeedsIndependentlyOfTheAngles) {
  auto max_start = [](const std::function<void(config::TossConfig*)>& edit) {
    auto spec = LoadTossSpec(config::CATCH, edit);
    const TossArmJoints& arm = spec->arm(Hand::kRight);
    double max_speed = 0, max_angle_offset = 0;
    for (uint64_t seed = 0; seed < 50; ++seed) {
      TossTaskEnv env(spec, Rng(seed));
      env.Reset(NoWalk());
      for (int j = 1; j < kTossJoints; ++j) {  // the neck starts centred
        max_speed = std::max(max_speed, std::abs(env.data()->qvel[arm.dof[j]]));
        max_angle_offset =
            std::max(max_angle_offset, std::abs(env.data()->qpos[arm.qpos[j]] - spec->home()[j]));
      }
    }
    return std::make_pair(max_speed, max_angle_offset);
  };
  const auto [default_speed, default_angle] =
      max_start([](config::TossConfig* t) {
        t->set_start_noise(0.2);
        t->clear_start_speed_noise();
      });
  EXPECT_LE(default_speed, 2.0);
  EXPECT_GT(default_speed, 1.5);
  EXPECT_LE(default_angle, 0.2);
  const auto [fast_speed, fast_angle] = max_start([](config::TossConfig* t) {
    t->set_start_noise(0.2);
    t->set_start_speed_noise(12);
  });
  EXPECT_LE(fast_speed, 12.0);
  EXPECT_GT(fast_speed, 9.0);
  EXPECT_LE(fast_angle, 0.2);
  EXPECT_GT(fast_angle, 0.15);
}

}  // namespace
}  // namespace juggle::toss
