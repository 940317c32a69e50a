// Football's kick as a planning task (planner/football/kick_task.h), found through the list of
// tasks and driven by the generic receding-horizon driver: on held-out starts it kicks closer to
// the target than the scripted kick with zero action, with every visited state as predicted,
// bit for bit; its actions replayed as plain actions in a fresh env give the same kick; it is
// deterministic for a seed across thread counts; its terms add up to its cost; a refinement on
// its signed errors lowers a plan's cost and kicks as predicted; and it refuses football runs it
// cannot plan, naming file, line and field.
#include "planner/football/kick_task.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/football/env.h"
#include "envs/football/outcomes.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "planner/planner_config.h"
#include "planner/receding_horizon.h"
#include "planner/tasks.h"
#include "planner/testing/shipped_task_test.h"

namespace juggle::planner {
namespace {

using ::juggle::testing::Loc;
using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kShippedKick[] = "configs/football_kick.textproto";

class FootballKickTaskTest : public testing::ShippedTaskTest {
 protected:
  void SetUp() override {
    Use(LoadRunConfig(RepoPath(kShippedKick)));
    ASSERT_EQ(task_->family(), "football");
  }
};

TEST_F(FootballKickTaskTest, KicksCloserToTheTargetThanZeroActionAndAsPredicted) {
  RolloutPool pool(spec_, 2);
  double zero_cost = 0, planned_cost = 0;
  for (uint64_t seed : {1000001, 1000004}) {
    SCOPED_TRACE(absl::StrCat("seed ", seed));
    const testing::Episode zero = Run(seed, nullptr);
    RecedingHorizonPlanner planner(task_, Settings(), &pool, seed);
    const testing::Episode planned = Run(seed, &planner);
    EXPECT_EQ(planned.end, football::kKicked);
    EXPECT_EQ(planned.Metric("kick_success"), 1);
    // Both deviations in the cost's units (2 degrees, 1 m/s), as the task weighs them.
    auto cost = [](const testing::Episode& k) {
      if (k.Metric("kick_success") < 0.5) return 1e4;
      return std::pow(k.Metric("kick_direction_deviation_deg") / 2, 2) +
             std::pow(k.Metric("kick_speed_deviation_mps"), 2);
    };
    zero_cost += cost(zero);
    planned_cost += cost(planned);
    EXPECT_GT(planner.totals().prediction_checks, 10);
    EXPECT_EQ(planner.totals().prediction_mismatches, 0);
    // The plan's actions replayed without the planner: the same kick, bit for bit.
    const testing::Episode replayed = Run(seed, nullptr, &planned.actions);
    EXPECT_EQ(replayed.final_qpos, planned.final_qpos);
    EXPECT_EQ(replayed.Metric("kick_direction_deviation_deg"),
              planned.Metric("kick_direction_deviation_deg"));
  }
  EXPECT_LT(planned_cost, 0.5 * zero_cost);
}

TEST_F(FootballKickTaskTest, TheSameSeedGivesTheSameKickOnAnyThreadCountAndAnotherSeedAnother) {
  ExpectActionsDependOnlyOnTheSeed(1000002);
}

TEST_F(FootballKickTaskTest, TheTermsAddUpToTheCost) {
  std::vector<double> theta(task_->dim(), 0.0);
  theta[1] = 0.3;  // more hip
  const std::unique_ptr<RolloutScorer> scorer =
      ExpectTermsAddUpToTheCost(3, theta, task_->horizon());
  EXPECT_EQ(scorer->first_outcome().size(), task_->outcome_names().size());
}

TEST_F(FootballKickTaskTest, TheRefinementLowersAPlansCostOnceTheTouchIsInTheHorizon) {
  // The same search with and without Levenberg–Marquardt steps on the kick's signed errors, at
  // each of the first states whose plan scores the kick (its touch and window inside the
  // horizon): the refined plan never costs more than the searched one (a step is kept only if
  // the cost falls) and costs less at some; the refined planner's episode kicks exactly as its
  // rollouts said.
  const uint64_t seed = 1000001;
  RolloutPool pool(spec_, 2);
  const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
  env->Reset(*walk_);
  std::vector<float> action(spec_->act_dim());
  config::PlannerConfig plain_settings = Settings();
  plain_settings.set_refine_iterations(0);
  RecedingHorizonPlanner driver(task_, plain_settings, &pool, seed);
  config::PlannerConfig refined_settings = Settings();
  refined_settings.set_refine_iterations(3);
  const config::FootballPlanning& f = config_.run.planner().football();
  int compared = 0, lowered = 0;
  for (int step = 0; step < 60 && compared < 4; ++step) {
    ASSERT_TRUE(driver.Act(*env, action.data()).ok());
    if (step % 3 == 0 && !driver.last_replan().predicted_outcome.empty()) {
      SCOPED_TRACE(absl::StrCat("step ", step));
      ++compared;
      std::vector<float> unused(spec_->act_dim());
      RecedingHorizonPlanner plain(task_, plain_settings, &pool, seed);
      ASSERT_TRUE(plain.Act(*env, unused.data()).ok());
      RecedingHorizonPlanner refined(task_, refined_settings, &pool, seed);
      ASSERT_TRUE(refined.Act(*env, unused.data()).ok());
      EXPECT_LE(refined.last_replan().best_cost, plain.last_replan().best_cost);
      if (refined.last_replan().best_cost < plain.last_replan().best_cost) ++lowered;
      EXPECT_GT(refined.totals().rollouts, plain.totals().rollouts);
      // The residuals are the signed errors in the cost's units.
      const std::vector<double>& outcome = refined.last_replan().predicted_outcome;
      ASSERT_EQ(outcome.size(), 6);
      double residuals[3];
      ASSERT_TRUE(task_->Residuals(outcome, residuals));
      EXPECT_DOUBLE_EQ(residuals[0],
                       std::sqrt(f.direction()) / f.direction_scale_deg() * outcome[3]);
      EXPECT_DOUBLE_EQ(residuals[2], std::sqrt(f.speed()) / f.speed_scale_mps() * outcome[5]);
    }
    if (env->Step(action.data(), *walk_).outcome != Outcome::kRunning) break;
  }
  ASSERT_GT(compared, 0) << "no plan scored the kick";
  EXPECT_GT(lowered, 0) << "the refinement lowered no plan's cost in " << compared;

  RecedingHorizonPlanner episode_planner(task_, refined_settings, &pool, seed);
  const testing::Episode kicked = Run(seed, &episode_planner);
  EXPECT_EQ(kicked.end, football::kKicked);
  EXPECT_GT(episode_planner.totals().prediction_checks, 10);
  EXPECT_EQ(episode_planner.totals().prediction_mismatches, 0);
}

// Writes `planner_block` over `base` as file `name`, loads it and validates its planner: the
// error's message must start at `field`'s file:line:col and contain `mentions`.
void ExpectRefusedAt(const char* name, const char* base, const std::string& planner_block,
                     const std::string& field, const std::string& mentions) {
  SCOPED_TRACE(name);
  const std::string text = absl::StrCat("base_config: \"", RepoPath(base), "\"\nplanner {\n  ",
                                        planner_block, "\n}\n");
  const std::string path = WriteTemp(name, text);
  absl::StatusOr<LoadedConfig> c = LoadRunConfig(path);
  ASSERT_TRUE(c.ok()) << c.status();
  const absl::Status s = ValidatePlannerConfig(*c);
  EXPECT_THAT(std::string(s.message()), StartsWith(Loc(path, text, field)));
  EXPECT_THAT(s.message(), HasSubstr(mentions));
}

TEST_F(FootballKickTaskTest, RunsItCannotPlanAreRefusedNamingFileLineAndField) {
  ExpectRefusedAt("football_long_horizon.textproto", kShippedKick, "horizon_steps: 5000",
                  "horizon_steps", "max_episode_steps");
  ExpectRefusedAt("football_two_kicks.textproto", kShippedKick, "football { kick { cycles: 2 } }",
                  "cycles", "one kick per episode");
  ExpectRefusedAt("football_no_room.textproto", kShippedKick,
                  "football { trap { keep_margin_m: 1 } }", "keep_margin_m", "reach_m");
  // The trap has no residuals: a refinement there would do nothing.
  ExpectRefusedAt("football_refined_trap.textproto", "configs/football_trap.textproto",
                  "rescue { refine_first: 2 }", "refine_first", "TRAP");
}

}  // namespace
}  // namespace juggle::planner
