// The planning model (envs/planning_model.h, PlannerConfig.planning_model) on the real
// simulator: its envs take the executed model's snapshots; with the executed options it steps
// bit for bit as the executed model; its prediction error on a fixed state (the zero-action
// kick from the apex of a DOWN node) is measured against the executed model and grows with the
// timestep; a bad factor is a clear error; and a planner on it still predicts the executed
// future bit for bit (the chosen plan is simulated on the executed model) while counting its
// checks.
#include "envs/planning_model.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/spec.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "planner/planning_pools.h"
#include "planner/receding_horizon.h"
#include "planner/soccer_juggle/cost.h"
#include "planner/soccer_juggle/task.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using ::testing::HasSubstr;

class PlanningModelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(::juggle::testing::RepoPath("configs/right_foot_planner.textproto"));
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }

  // The executed model's env at the apex of a DOWN node (a fixed state).
  std::unique_ptr<JuggleEnv> ApexEnv() {
    auto env = std::make_unique<JuggleEnv>(Juggle(spec_), Rng(3));
    env->ResetAt(*spec_->graph().FindNode("right_foot_down"), *walk_);
    return env;
  }
  static std::shared_ptr<const JuggleSpec> Juggle(const std::shared_ptr<const EnvSpec>& s) {
    return std::dynamic_pointer_cast<const JuggleSpec>(s);
  }
  // Zero action from `snapshot` on `spec`'s model until the kick leaves the foot: its predicted
  // landing, and the steps it took (invalid if none within 60 steps).
  KickOutcome ZeroActionKick(const std::shared_ptr<const EnvSpec>& spec,
                             const EnvSnapshot& snapshot, int* steps) {
    JuggleEnv env(Juggle(spec), Rng(0));
    EXPECT_TRUE(env.Restore(snapshot).ok());
    const float zero[kNumActions] = {0};
    for (*steps = 1; *steps <= 60; ++*steps) {
      if (env.Step(zero, *walk_).outcome != Outcome::kRunning) return {};
      if (env.state().kick_touched && !env.state().touched_this_step) {
        return PredictKickOutcome(env);
      }
    }
    return {};
  }

  LoadedConfig config_;
  std::shared_ptr<const EnvSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(PlanningModelTest, ATimestepFactorThatDoesNotDivideTheSubstepsIsAClearError) {
  PlanningModelOptions o;
  o.timestep_factor = 3;
  const absl::StatusOr<std::shared_ptr<const EnvSpec>> bad = CreatePlanningSpec(spec_, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(bad.status().message(),
              HasSubstr("planner.planning_model.timestep_factor 3 does not divide the env's 8 substeps"));
}

TEST_F(PlanningModelTest, WithTheExecutedOptionsItStepsBitForBitAsTheExecutedModel) {
  PlanningModelOptions o;
  o.solver_iterations = spec_->model()->opt.iterations;  // a variant, with the same physics
  const absl::StatusOr<std::shared_ptr<const EnvSpec>> same = CreatePlanningSpec(spec_, o);
  ASSERT_TRUE(same.ok()) << same.status();
  EXPECT_EQ((*same)->fingerprint(), spec_->fingerprint()) << "it takes the executed model's snapshots";
  std::unique_ptr<JuggleEnv> exact = ApexEnv();
  JuggleEnv variant(Juggle(*same), Rng(0));
  ASSERT_TRUE(variant.Restore(*exact->Snapshot()).ok());
  const float zero[kNumActions] = {0};
  for (int t = 0; t < 40; ++t) {
    exact->Step(zero, *walk_);
    variant.Step(zero, *walk_);
  }
  EXPECT_EQ(StateFingerprint(*exact, spec_->model()), StateFingerprint(variant, spec_->model()));
}

// The kick-landing error of each planning model against the executed one, from one fixed
// state: printed, and ordered as the timestep grows.
TEST_F(PlanningModelTest, ItsKickPredictionErrorIsMeasuredAndGrowsWithTheTimestep) {
  const std::unique_ptr<EnvSnapshot> apex = ApexEnv()->Snapshot();
  int exact_steps = 0;
  const KickOutcome exact = ZeroActionKick(spec_, *apex, &exact_steps);
  ASSERT_TRUE(exact.valid) << "the base controller's zero-action kick did not leave the foot";
  struct Row {
    const char* name;
    PlanningModelOptions options;
    double landing_error = 0, timing_error = 0;
  };
  std::vector<Row> rows(4);
  rows[0].name = "solver 5 iterations, tolerance 1e-4";
  rows[0].options.solver_iterations = 5;
  rows[0].options.solver_tolerance = 1e-4;
  rows[1].name = "timestep 2x";
  rows[1].options.timestep_factor = 2;
  rows[2].name = "timestep 4x";
  rows[2].options.timestep_factor = 4;
  rows[3].name = "pyramidal cones";
  rows[3].options.pyramidal_cone = true;
  for (Row& row : rows) {
    const absl::StatusOr<std::shared_ptr<const EnvSpec>> planning = CreatePlanningSpec(spec_, row.options);
    ASSERT_TRUE(planning.ok()) << planning.status();
    int steps = 0;
    const KickOutcome k = ZeroActionKick(*planning, *apex, &steps);
    if (!k.valid) {  // the planning model loses the kick altogether
      row.landing_error = row.timing_error = std::numeric_limits<double>::infinity();
      std::printf("%-36s no kick: the ball never leaves the foot toward the next contact\n", row.name);
      continue;
    }
    row.landing_error = std::hypot(k.dx - exact.dx, k.dy - exact.dy);
    row.timing_error = std::abs(k.timing - exact.timing);
    std::printf("%-36s landing %.4f m, timing %.4f s from the executed model's kick\n", row.name,
                row.landing_error, row.timing_error);
  }
  EXPECT_LT(rows[0].landing_error, 0.01) << "a looser solver should barely move the kick";
  EXPECT_GT(rows[2].landing_error, rows[1].landing_error) << "4x coarser errs more than 2x";
  EXPECT_GT(rows[1].landing_error, 0) << "a coarser timestep changes the kick";
}

TEST_F(PlanningModelTest, APlannerOnItStillPredictsTheExecutedFutureBitForBit) {
  config::PlannerConfig p = config_.run.planner();
  p.set_samples(8);
  p.set_iterations(2);
  p.set_horizon_steps(32);
  p.set_replan_every(4);
  p.mutable_planning_model()->set_timestep_factor(2);
  absl::StatusOr<PlanningPools> pools = MakePlanningPools(spec_, p, 2);
  ASSERT_TRUE(pools.ok()) << pools.status();
  ASSERT_NE(pools->exact, nullptr);
  RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(Juggle(spec_), p), p,
                                 pools->search.get(), 0, nullptr, pools->exact.get());
  std::unique_ptr<JuggleEnv> env = ApexEnv();
  float action[kNumActions];
  for (int t = 0; t < 60; ++t) {
    ASSERT_TRUE(planner.Act(*env, action).ok());
    if (env->Step(action, *walk_).outcome != Outcome::kRunning) break;
  }
  const PlannerTotals& t = planner.totals();
  EXPECT_GT(t.replans, 5);
  EXPECT_EQ(t.model_checks, t.replans) << "every choice simulated on the executed model";
  EXPECT_GT(t.exact_rollouts, t.replans) << "the choice and the warm start beside it";
  EXPECT_GT(t.prediction_checks, 20);
  EXPECT_EQ(t.prediction_mismatches, 0) << "the prediction is the executed model's";
}

// Multi-fidelity rollouts (PlanningModel.exact_within_m): within the distance the state moves to
// the executed model. Within 100 m every step is the executed model's, so a candidate costs
// exactly what it costs on the executed model; without it the 2x model's cost differs; within
// 0.6 m a planner's search simulates part of its steps on each model.
TEST_F(PlanningModelTest, AMultiFidelityRolloutIsTheExecutedModelsNearTheContact) {
  config::PlannerConfig p = config_.run.planner();
  p.set_samples(8);
  p.set_iterations(2);
  p.set_horizon_steps(32);
  p.mutable_rescue()->set_cost_above(0);  // no rescue: a quick test
  auto cost_with = [&](const config::PlannerConfig& c) -> double {
    absl::StatusOr<PlanningPools> pools = MakePlanningPools(spec_, c, 1);
    EXPECT_TRUE(pools.ok()) << pools.status();
    RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(Juggle(spec_), c), c,
                                   pools->search.get(), 0, nullptr, pools->exact.get());
    std::unique_ptr<JuggleEnv> env = ApexEnv();
    const absl::StatusOr<double> cost =
        planner.Evaluate(*env, std::vector<double>(planner.task().dim(), 0.0));
    EXPECT_TRUE(cost.ok()) << cost.status();
    return cost.value_or(-1);
  };
  const double exact = cost_with(p);
  config::PlannerConfig coarse = p;
  coarse.mutable_planning_model()->set_timestep_factor(2);
  config::PlannerConfig everywhere = coarse;
  everywhere.mutable_planning_model()->set_exact_within_m(100);
  EXPECT_EQ(cost_with(everywhere), exact) << "every step on the executed model";
  EXPECT_NE(cost_with(coarse), exact) << "the 2x model's cost differs";

  config::PlannerConfig near = coarse;
  near.mutable_planning_model()->set_exact_within_m(0.6);
  absl::StatusOr<PlanningPools> pools = MakePlanningPools(spec_, near, 2);
  ASSERT_TRUE(pools.ok()) << pools.status();
  RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(Juggle(spec_), near), near,
                                 pools->search.get(), 0, nullptr, pools->exact.get());
  std::unique_ptr<JuggleEnv> env = ApexEnv();
  float action[kNumActions];
  for (int t = 0; t < 12; ++t) {
    ASSERT_TRUE(planner.Act(*env, action).ok());
    env->Step(action, *walk_);
  }
  const PlannerTotals& t = planner.totals();
  EXPECT_GT(t.rollout_steps, 0) << "steps on the planning model";
  EXPECT_GT(t.exact_rollout_steps, 3 * t.replans * 2) << "steps of the search on the executed model";
  EXPECT_EQ(t.prediction_mismatches, 0);
}

}  // namespace
}  // namespace juggle::planner
