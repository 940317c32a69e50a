// The toss base controllers (envs/toss/base_controller.h) and their parts, each checked by an
// independent path: the closed-form arm kinematics against MuJoCo's forward kinematics and site
// Jacobian, the discrete plan against plain Euler arithmetic, the inverse-dynamics targets
// against the acceleration a real TossWorld::Step produces, the throws against the schedule's
// velocity (Eq. 1-3) and the catches and juggling against the real runtime.
#include <cmath>
#include <memory>

#include <mujoco/mujoco.h>

#include "gtest/gtest.h"
#include "common/rng.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/arm_kinematics.h"
#include "envs/toss/arm_tracking.h"
#include "envs/toss/base_controller.h"
#include "envs/toss/juggler.h"

namespace juggle::toss {
namespace {

std::shared_ptr<const TossSpec> BaseSpec(double wind = 0) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/toss_base.textproto"));
  EXPECT_TRUE(config.ok()) << config.status();
  config->run.mutable_toss()->set_wind_force(wind);
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return *spec;
}

TEST(ArmKinematicsTest, PalmAndJacobianMatchMujocoForRandomPoses) {
  auto spec = BaseSpec();
  const ArmGeometry g = ReadArmGeometry(*spec);
  const mjModel* m = spec->model();
  MjDataPtr data(mj_makeData(m));
  const TossArmJoints& arm = spec->arm(Hand::kRight);
  Rng rng = Rng::ForStream(7, 0, 0);
  std::vector<mjtNum> jacp(3 * m->nv);
  for (int trial = 0; trial < 20; ++trial) {
    const ArmAngles q = {rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-1.4, 1.4)};
    for (int j = 0; j < 3; ++j) data->qpos[arm.qpos[j + 1]] = q[j];
    mj_forward(m, data.get());
    const Vec2 p = PalmPosition(g, q);
    EXPECT_NEAR(p.x, data->site_xpos[3 * arm.palm_site], 1e-12);
    EXPECT_NEAR(p.z, data->site_xpos[3 * arm.palm_site + 2], 1e-12);
    mj_jacSite(m, data.get(), jacp.data(), nullptr, arm.palm_site);
    const std::array<ArmAngles, 2> jac = PalmJacobian(g, q);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(jac[0][j], jacp[arm.dof[j + 1]], 1e-12);
      EXPECT_NEAR(jac[1][j], jacp[2 * m->nv + arm.dof[j + 1]], 1e-12);
    }
  }
}

TEST(ArmKinematicsTest, InverseKinematicsReachesThePointWithTheHandAngleAndHomeIsItsAnswer) {
  auto spec = BaseSpec();
  const ArmGeometry g = ReadArmGeometry(*spec);
  const ArmAngles home = {spec->home()[1], spec->home()[2], spec->home()[3]};
  const std::optional<ArmAngles> at_home =
      SolveArmIk(g, {spec->toss().hand_x(), spec->home_z()}, HandAngle(home));
  ASSERT_TRUE(at_home.has_value());
  for (int j = 0; j < 3; ++j) EXPECT_NEAR((*at_home)[j], home[j], 1e-9);
  for (const Vec2 target : {Vec2{-0.45, 0.9}, Vec2{0.05, 1.05}, Vec2{-0.2, 0.85}}) {
    const std::optional<ArmAngles> q = SolveArmIk(g, target, 0.3);
    ASSERT_TRUE(q.has_value());
    const Vec2 p = PalmPosition(g, *q);
    EXPECT_NEAR(p.x, target.x, 1e-9);
    EXPECT_NEAR(p.z, target.z, 1e-9);
    EXPECT_NEAR(HandAngle(*q), 0.3, 1e-12);
  }
  EXPECT_FALSE(SolveArmIk(g, {-0.2, 0.0}, 0.0).has_value());  // 1.4 m below the shoulder
}

TEST(ArmKinematicsTest, JointSpeedsMoveThePalmAtTheAskedVelocity) {
  auto spec = BaseSpec();
  const ArmGeometry g = ReadArmGeometry(*spec);
  const ArmAngles q = {0.4, 1.3, -0.2};
  const Vec2 v{0.3, 6.9};
  for (double wrist_weight : {1.0, 4.0, 100.0}) {
    const ArmAngles qd = JointSpeedsFor(g, q, v, wrist_weight);
    const std::array<ArmAngles, 2> jac = PalmJacobian(g, q);
    double vx = 0, vz = 0;
    for (int j = 0; j < 3; ++j) {
      vx += jac[0][j] * qd[j];
      vz += jac[1][j] * qd[j];
    }
    EXPECT_NEAR(vx, v.x, 1e-9);
    EXPECT_NEAR(vz, v.z, 1e-9);
  }
  // A heavier wrist weight keeps the wrist out of it.
  EXPECT_LT(std::abs(JointSpeedsFor(g, q, v, 100.0)[2]), std::abs(JointSpeedsFor(g, q, v, 1.0)[2]));
}

TEST(ArmTrackingTest, ReplannedAccelerationsReachTheGoalStateExactlyInTheGivenSteps) {
  const double h = 0.01;
  for (int steps : {1, 2, 5, 35}) {
    ArmAngles q = {0.1, -0.3, 0.2}, v = {2.0, -1.0, 0.0};
    const ArmAngles q_goal = {-0.4, 1.5, 0.0}, v_goal = {10.0, -6.0, 1.0};
    for (int k = steps; k >= 1; --k) {
      const ArmAngles a = FirstPlannedAcceleration(q, v, q_goal, v_goal, k, h);
      for (int j = 0; j < 3; ++j) {
        v[j] += h * a[j];  // semi-implicit Euler, as MuJoCo's
        q[j] += h * v[j];
      }
    }
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(v[j], v_goal[j], 1e-9) << steps << " steps, joint " << j;
      if (steps > 1) {
        EXPECT_NEAR(q[j], q_goal[j], 1e-9) << steps << " steps, joint " << j;
      }
    }
  }
}

TEST(ArmTrackingTest, TargetsGiveTheAskedAccelerationInARealStepForBothArmsWithABallHeld) {
  auto spec = BaseSpec();
  TossWorld world(spec);
  Rng rng = Rng::ForStream(3, 0, 0);
  world.Reset(&rng, 0.4, 5.0);
  world.Hold(0, Hand::kLeft);
  const ArmAngles qacc = {35.0, -80.0, 12.0};
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const ArmAngles t = TargetsForAcceleration(world, hand, qacc);
    world.SetTargets(hand, {TossSpec::MirrorSign(hand) * spec->home()[0], t[0], t[1], t[2]});
  }
  const TossArmState right_before = world.ArmState(Hand::kRight);
  const TossArmState left_before = world.ArmState(Hand::kLeft);
  world.Step();
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const TossArmState& before = hand == Hand::kRight ? right_before : left_before;
    const TossArmState after = world.ArmState(hand);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR((after.speed[j + 1] - before.speed[j + 1]) / spec->dt(), qacc[j], 1e-6)
          << HandName(hand) << " joint " << j;
    }
  }
}

// Drives one world with the base throw for `value` from `hand` and returns the palm velocity
// after `steps` steps (when the runtime releases).
Vec2 ThrowFromHome(std::shared_ptr<const TossSpec> spec, Hand hand, int value, int steps) {
  const TossBaseController base(spec);
  TossWorld world(spec);
  world.Hold(0, hand);
  const Vec2 velocity = base.ReleaseVelocity(hand, value, 0);
  for (int k = steps; k >= 1; --k) {
    world.SetTargets(hand, base.WithResidual(hand, base.Throw(world, hand, k, velocity), nullptr));
    world.Step();
  }
  return world.palm_velocity(hand);
}

TEST(TossBaseControllerTest, ReleaseVelocityIsTheSchedulesInStillAir) {
  auto spec = BaseSpec();
  const TossBaseController base(spec);
  for (int value = 3; value <= 7; ++value) {
    for (int beat : {0, 1}) {
      const Hand hand = beat == 0 ? Hand::kRight : Hand::kLeft;
      const ThrowTiming timing = ComputeThrowTiming(value, beat, spec->timing());
      const Vec2 v = base.ReleaseVelocity(hand, value, 0);
      EXPECT_NEAR(v.x, timing.v_x, 1e-12) << value;
      EXPECT_NEAR(v.z, timing.v_z, 1e-12) << value;
    }
  }
}

TEST(TossBaseControllerTest, ThrowsFromRestAtHomeLeaveWithinAMillimetrePerSecondOfTheSchedule) {
  auto spec = BaseSpec();
  const TossBaseController base(spec);
  for (int value = 3; value <= 7; ++value) {
    for (Hand hand : {Hand::kRight, Hand::kLeft}) {
      const Vec2 target = base.ReleaseVelocity(hand, value, 0);
      const Vec2 v = ThrowFromHome(spec, hand, value, 35);  // a dwell of D_ratio·P_hand
      EXPECT_LT(std::hypot(v.x - target.x, v.z - target.z), 1e-3)
          << value << " from " << HandName(hand) << ": (" << v.x << ", " << v.z << ")";
    }
  }
}

TEST(TossBaseControllerTest, CatchesAFastBallThatLandsOffCentre) {
  auto spec = BaseSpec();
  const TossBaseController base(spec);
  TossWorld world(spec);
  // A 7 coming down 12 cm outside the right hand's home point, 0.3 s from hand height.
  const double g = spec->timing().gravity, t = 0.3, vz = -6.0;
  const double z0 = spec->home_z() - vz * t + 0.5 * g * t * t;
  const double x_land = spec->home_x(Hand::kRight) - 0.12;
  world.SetFree(0, {x_land - 0.1 * t, z0}, {0.1, vz + g * t});
  bool caught = false;
  for (int k = 0; k < 60 && !caught; ++k) {
    world.SetTargets(Hand::kRight, base.WithResidual(Hand::kRight,
                                                     base.Catch(world, Hand::kRight, 0, 0), nullptr));
    world.Step();
    caught = world.CanCatch(0, Hand::kRight);
  }
  ASSERT_TRUE(caught);
  // The hand went out to the landing point (at home the ball would pass 12 cm away, beyond the
  // 7 cm catch radius) and met the ball at hand height.
  const Vec2 palm = world.palm_position(Hand::kRight);
  EXPECT_NEAR(palm.x, x_land, 0.02);
  EXPECT_NEAR(palm.z, spec->home_z(), 0.02);
}

TEST(TossBaseControllerTest, WindEstimateIsTheForceOverTheBallsMass) {
  const double wind = 0.3;
  auto spec = BaseSpec(wind);
  TossWorld world(spec);
  world.SetFree(2, {0.0, 1.5}, {0.5, 3.0});
  WindEstimator estimator;
  EXPECT_EQ(estimator.accel(), 0.0);
  estimator.BeforeStep(world);
  world.Step();
  estimator.AfterStep(world);
  const mjModel* m = spec->model();
  const double mass = m->body_mass[m->dof_bodyid[spec->ball(2).dof_x]];
  EXPECT_NEAR(estimator.accel(), wind / mass, 1e-9);
}

// The single-arm tasks with toss.base: a zero residual throws on target and catches.
TEST(TaskEnvWithBaseTest, ZeroResidualThrowsOnTargetAndCatchesInTheSingleArmTasks) {
  for (config::TossTask task : {config::THROW, config::CATCH}) {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(testing::RepoPath("configs/toss_base.textproto"));
    ASSERT_TRUE(config.ok()) << config.status();
    config->run.mutable_toss()->set_task(task);
    auto spec = TossSpec::Create(*config);
    ASSERT_TRUE(spec.ok()) << spec.status();
    std::unique_ptr<Env> env = (*spec)->NewEnv(Rng::ForStream(1, 0, 0));
    const AdaptiveWalk walk(&(*spec)->graph());
    const float zero[kTossJoints] = {0, 0, 0, 0};
    int completions = 0;
    for (int episode = 0; episode < 20; ++episode) {
      env->Reset(walk);
      while (env->Step(zero, walk).outcome == Outcome::kRunning) {
      }
      completions += env->completions();
    }
    // Catch starts are as wide as a throw's follow-through (± 0.5 rad, ± 12 rad/s) and balls
    // land up to 15 cm off: the base still catches nearly all; throws are exact.
    EXPECT_GE(completions, task == config::THROW ? 20 : 18) << config::TossTask_Name(task);
  }
}

class ZeroResidualTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ZeroResidualTest, BaseControllersAloneJuggleThePatternToTheCapFromNoisyStarts) {
  for (uint64_t seed : {11, 12}) {
    JugglerOptions options;
    options.max_throws = 100;
    options.seed = seed;  // start noise 0.05 rad, balls ± 2 cm, ± 0.1 m/s
    absl::StatusOr<std::unique_ptr<TossJuggler>> juggler =
        TossJuggler::Create(BaseSpec(), *Siteswap::Parse(GetParam()), TossPolicies{}, options);
    ASSERT_TRUE(juggler.ok()) << juggler.status();
    const JuggleRunResult r = (*juggler)->Run();
    EXPECT_EQ(r.throws, 100) << GetParam() << " seed " << seed << ": " << JuggleEndName(r.end);
    EXPECT_LT(r.mean_velocity_error, 0.05) << GetParam();
  }
}

INSTANTIATE_TEST_SUITE_P(Patterns, ZeroResidualTest,
                         ::testing::Values("3", "4", "5", "6", "7", "53", "441", "531"),
                         [](const auto& info) { return std::string("pattern_") + info.param; });

TEST(ZeroResidualWindTest, BaseControllersHoldThreeInAWindFiveTimesTheOldPairsLimit) {
  JugglerOptions options;
  options.max_throws = 100;
  auto calm = TossJuggler::Create(BaseSpec(0.7), *Siteswap::Parse("3"), TossPolicies{}, options);
  ASSERT_TRUE(calm.ok());
  EXPECT_EQ((*calm)->Run().throws, 100);
}

}  // namespace
}  // namespace juggle::toss
