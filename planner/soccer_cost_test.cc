// The impact acceleration (planner/soccer_cost.h, ImpactTracker) on the real simulator: it
// agrees with the kicking foot's velocity from a separate forward pass, a tracker begun one step
// before the touch measures it too, and the planner's cost on it is the squared distance
// outside its band.
#include "planner/soccer_cost.h"

#include <cmath>
#include <memory>
#include <vector>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/rollout_pool.h"
#include "planner/soccer_planner.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

class ImpactAccelerationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(testing::RepoPath("configs/right_foot_planner.textproto"));
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    config::PlannerConfig& p = *config_.run.mutable_planner();
    p.set_samples(16);
    p.set_iterations(4);
    p.set_horizon_steps(32);
    p.set_body_knot_steps(0);
    p.mutable_rescue()->set_cost_above(0);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::dynamic_pointer_cast<const JuggleSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    down_ = *spec_->graph().FindNode("right_foot_down");
  }

  // An env at the apex of the DOWN node (its start varied by `seed`).
  std::unique_ptr<JuggleEnv> Start(uint64_t seed) {
    auto env = std::make_unique<JuggleEnv>(spec_, Rng(seed));
    env->ResetAt(down_, *walk_);
    return env;
  }

  LoadedConfig config_;
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  int down_ = -1;
};

// Every body's centre-of-mass velocity (3 per body, world axes) from a fresh forward pass on a
// copy of `d`: the spatial velocities at the step's end.
std::vector<double> VelocitiesAfterForward(const mjModel* m, const mjData* d) {
  mjData* copy = mj_copyData(nullptr, m, d);
  mj_forward(m, copy);
  std::vector<double> v(3 * m->nbody, 0.0);
  for (int b = 1; b < m->nbody; ++b) {
    double spatial[6];
    mj_objectVelocity(m, copy, mjOBJ_BODY, b, spatial, 0);
    mju_copy3(v.data() + 3 * b, spatial + 3);
  }
  mj_deleteData(copy);
  return v;
}

TEST_F(ImpactAccelerationTest, AgreesWithTheFootsVelocityFromAForwardPass) {
  const mjModel* m = spec_->model();
  const double dt = spec_->control_dt();
  const float zero[kNumActions] = {0};
  int measured = 0;
  std::vector<uint64_t> touch_seeds;
  std::vector<int> touch_steps;
  std::vector<double> impacts;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    std::unique_ptr<JuggleEnv> env = Start(seed);
    ImpactTracker tracker;
    tracker.Begin(*env);
    std::vector<std::vector<double>> velocities = {VelocitiesAfterForward(m, env->data())};
    std::vector<double> ball = {env->data()->qvel + spec_->ball_dof(),
                                env->data()->qvel + spec_->ball_dof() + 3};
    for (int t = 0; t < 60; ++t) {
      const bool touched_before = env->state().kick_touched;
      if (env->Step(zero, *walk_).outcome != Outcome::kRunning) break;
      const double impact = tracker.AfterStep(*env);
      const mjData* d = env->data();
      if (env->state().kick_touched && !touched_before) {
        ASSERT_TRUE(std::isfinite(impact)) << "seed " << seed << " step " << t;
        touch_seeds.push_back(seed);
        touch_steps.push_back(t);
        impacts.push_back(impact);
        // The impulse's direction from the ball's velocity change, gravity taken out.
        double n[3];
        for (int i = 0; i < 3; ++i) n[i] = d->qvel[spec_->ball_dof() + i] - ball[i];
        n[2] += spec_->env().gravity() * dt;
        mju_normalize3(n);
        EXPECT_GT(n[2], 0.5) << "a foot kick sends the ball up";
        // The touching body: the foot (the node also allows the shin, which a kick from the
        // apex start does not use).
        const int body = mj_name2id(m, mjOBJ_BODY, "right_ankle");
        ASSERT_GT(body, 0);
        EXPECT_EQ(env->state().touched_body, body);
        const std::vector<double>& one = velocities[velocities.size() - 1];
        const std::vector<double>& two = velocities[velocities.size() - 2];
        double expected = 0;
        for (int i = 0; i < 3; ++i) expected += (one[3 * body + i] - two[3 * body + i]) * n[i];
        expected /= dt;
        // The tracker's Jacobians are of the last substep's start, one substep earlier.
        EXPECT_NEAR(impact, expected, 0.02 * std::abs(expected) + 0.2) << "seed " << seed;
        EXPECT_LT(impact, 0) << "the base controller's swing meets the ball decelerating";
        ++measured;
        break;
      }
      EXPECT_FALSE(std::isfinite(impact)) << "no first touch at step " << t;
      velocities.push_back(VelocitiesAfterForward(m, d));
      ball.assign(d->qvel + spec_->ball_dof(), d->qvel + spec_->ball_dof() + 3);
    }
  }
  EXPECT_GE(measured, 3) << "the base controller kicks from most apex starts";

  // A tracker begun one step before the touch (history from the state's acceleration) measures
  // the same kick nearly alike.
  for (size_t k = 0; k < touch_steps.size(); ++k) {
    std::unique_ptr<JuggleEnv> env = Start(touch_seeds[k]);
    for (int t = 0; t < touch_steps[k]; ++t) {
      ASSERT_EQ(env->Step(zero, *walk_).outcome, Outcome::kRunning);
    }
    ImpactTracker late;
    late.Begin(*env);
    env->Step(zero, *walk_);
    EXPECT_NEAR(late.AfterStep(*env), impacts[k], 0.1 * std::abs(impacts[k]) + 0.5)
        << "seed " << touch_seeds[k];
  }
}

// The cost adds weight × (distance outside [min, max] / scale)² for the kick, nothing inside.
TEST_F(ImpactAccelerationTest, ItsCostIsTheSquaredDistanceOutsideItsBandPerKick) {
  RolloutPool pool(spec_, 2);
  std::unique_ptr<JuggleEnv> env = Start(3);
  auto cost_of_zero_plan = [&](double weight, double min, double max, KickOutcome* kick) {
    config::PlannerCost& cost = *config_.run.mutable_planner()->mutable_cost();
    cost.set_impact_acceleration(weight);
    cost.set_impact_acceleration_min(min);
    cost.set_impact_acceleration_max(max);
    cost.set_impact_acceleration_scale(4);
    SoccerPlanner planner(spec_, config_.run.planner(), &pool, 0);
    const std::vector<double> zero(planner.layout().dim(), 0.0);
    absl::StatusOr<double> c = planner.Evaluate(*env, zero, kick);
    EXPECT_TRUE(c.ok()) << c.status();
    return c.value_or(0);
  };
  KickOutcome kick;
  const double free = cost_of_zero_plan(0, -1000, 0, &kick);
  ASSERT_TRUE(kick.valid);
  const double a = kick.impact_acceleration;
  ASSERT_TRUE(std::isfinite(a));
  ASSERT_LT(free, 1e4) << "the zero plan kicks without failing inside the horizon";
  const double tolerance = 1e-6;
  EXPECT_NEAR(cost_of_zero_plan(7, -1000, a - 2, &kick) - free, 7 * 0.25, tolerance);
  EXPECT_NEAR(cost_of_zero_plan(7, a + 6, 1000, &kick) - free, 7 * 2.25, tolerance);
  EXPECT_NEAR(cost_of_zero_plan(7, a - 1, a + 1, &kick) - free, 0, tolerance);
}

}  // namespace
}  // namespace juggle::planner
