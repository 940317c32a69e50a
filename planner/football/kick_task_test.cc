// Football's kick as a planning task (planner/football/kick_task.h), found through the list of
// tasks and driven by the generic receding-horizon driver: on held-out starts it kicks closer to
// the target than the scripted kick with zero action, with every visited state as predicted,
// bit for bit; its actions replayed as plain actions in a fresh env give the same kick; it is
// deterministic for a seed across thread counts; its terms add up to its cost; and it refuses
// football runs it cannot plan, naming file, line and field.
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

namespace juggle::planner {
namespace {

using ::juggle::testing::Loc;
using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kShipped[] = "configs/football_kick.textproto";

// One kick episode: how it ended, its metrics and the actions that made it.
struct Kick {
  Outcome end = Outcome::kRunning;
  bool success = false;
  double kdd = 0, ksd = 0;
  std::vector<float> actions;
  std::vector<double> final_qpos;
};

class FootballKickTaskTest : public ::testing::Test {
 protected:
  void SetUp() override { Use(LoadRunConfig(RepoPath(kShipped))); }

  void Use(absl::StatusOr<LoadedConfig> config) {
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *std::move(config);
    ASSERT_TRUE(ValidatePlannerConfig(config_).ok()) << ValidatePlannerConfig(config_);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    absl::StatusOr<std::shared_ptr<const PlanningTask>> task =
        MakePlanningTask(spec_, config_.run.planner());
    ASSERT_TRUE(task.ok()) << task.status();
    task_ = *task;
    ASSERT_EQ(task_->family(), "football");
  }

  // Kicks once from the start of env seed `seed`: with `planner`, with `replay`'s actions, or
  // with zero action.
  Kick Run(uint64_t seed, RecedingHorizonPlanner* planner, const std::vector<float>* replay = nullptr) {
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    Kick k;
    std::vector<float> a(spec_->act_dim(), 0.0f);
    for (int step = 0; step < 1000 && k.end == Outcome::kRunning; ++step) {
      if (planner != nullptr) {
        EXPECT_TRUE(planner->Act(*env, a.data()).ok());
      }
      if (replay != nullptr) std::copy_n(replay->begin() + step * a.size(), a.size(), a.begin());
      k.actions.insert(k.actions.end(), a.begin(), a.end());
      k.end = env->Step(a.data(), *walk_).outcome;
    }
    std::vector<NamedValue> metrics;
    env->AppendEpisodeMetrics(&metrics);
    for (const NamedValue& m : metrics) {
      if (m.name == "kick_success") k.success = m.value > 0.5;
      if (m.name == "kick_direction_deviation_deg") k.kdd = m.value;
      if (m.name == "kick_speed_deviation_mps") k.ksd = m.value;
    }
    k.final_qpos.assign(env->data()->qpos, env->data()->qpos + spec_->model()->nq);
    return k;
  }

  config::PlannerConfig Settings(uint64_t seed = 1) const {
    config::PlannerConfig p = config_.run.planner();
    p.set_seed(seed);
    return p;
  }

  LoadedConfig config_;
  std::shared_ptr<const EnvSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  std::shared_ptr<const PlanningTask> task_;
};

TEST_F(FootballKickTaskTest, KicksCloserToTheTargetThanZeroActionAndAsPredicted) {
  RolloutPool pool(spec_, 2);
  double zero_cost = 0, planned_cost = 0;
  for (uint64_t seed : {1000001, 1000004}) {
    SCOPED_TRACE(absl::StrCat("seed ", seed));
    const Kick zero = Run(seed, nullptr);
    RecedingHorizonPlanner planner(task_, Settings(), &pool, seed);
    const Kick planned = Run(seed, &planner);
    EXPECT_EQ(planned.end, football::kKicked);
    EXPECT_TRUE(planned.success);
    // Both deviations in the cost's units (2 degrees, 1 m/s), as the task weighs them.
    zero_cost += zero.success ? std::pow(zero.kdd / 2, 2) + std::pow(zero.ksd, 2) : 1e4;
    planned_cost += std::pow(planned.kdd / 2, 2) + std::pow(planned.ksd, 2);
    EXPECT_GT(planner.totals().prediction_checks, 10);
    EXPECT_EQ(planner.totals().prediction_mismatches, 0);
    // The plan's actions replayed without the planner: the same kick, bit for bit.
    const Kick replayed = Run(seed, nullptr, &planned.actions);
    EXPECT_EQ(replayed.final_qpos, planned.final_qpos);
    EXPECT_EQ(replayed.kdd, planned.kdd);
  }
  EXPECT_LT(planned_cost, 0.5 * zero_cost);
}

TEST_F(FootballKickTaskTest, TheSameSeedGivesTheSameKickOnAnyThreadCountAndAnotherSeedAnother) {
  config::PlannerConfig small = Settings(1);
  small.set_samples(6);
  small.set_iterations(2);
  RolloutPool one(spec_, 1), two(spec_, 2);
  RecedingHorizonPlanner a(task_, small, &one, 0), b(task_, small, &two, 0);
  config::PlannerConfig other = small;
  other.set_seed(2);
  RecedingHorizonPlanner c(task_, other, &one, 0);
  const Kick first = Run(1000002, &a);
  EXPECT_EQ(Run(1000002, &b).actions, first.actions);
  EXPECT_NE(Run(1000002, &c).actions, first.actions);
}

TEST_F(FootballKickTaskTest, TheTermsAddUpToTheCost) {
  const std::unique_ptr<Env> env = spec_->NewEnv(Rng(3));
  env->Reset(*walk_);
  std::vector<double> theta(task_->dim(), 0.0);
  theta[1] = 0.3;  // more hip
  std::unique_ptr<RolloutScorer> scorer = task_->NewScorer();
  scorer->Begin(*env);
  std::vector<float> a(spec_->act_dim());
  StepResult r;
  for (int step = 0; step < task_->horizon() && r.outcome == Outcome::kRunning; ++step) {
    task_->Action(*env, theta.data(), {step, 0}, nullptr, a.data());
    r = env->Step(a.data(), *walk_);
    scorer->AfterStep(*env, a.data(), r);
  }
  const double total = scorer->Finish(*env);
  double sum = 0;
  for (double t : scorer->terms()) sum += t;
  EXPECT_NEAR(sum, total, 1e-9 * std::max(1.0, total));
  EXPECT_EQ(scorer->terms().size(), task_->term_names().size());
  EXPECT_EQ(scorer->first_outcome().size(), task_->outcome_names().size());
}

TEST_F(FootballKickTaskTest, RunsItCannotPlanAreRefusedNamingFileLineAndField) {
  const std::string long_horizon = absl::StrCat(
      "base_config: \"", RepoPath(kShipped), "\"\nplanner {\n  horizon_steps: 5000\n}\n");
  const std::string path = WriteTemp("football_long_horizon.textproto", long_horizon);
  absl::StatusOr<LoadedConfig> c = LoadRunConfig(path);
  ASSERT_TRUE(c.ok()) << c.status();
  absl::Status s = ValidatePlannerConfig(*c);
  EXPECT_THAT(std::string(s.message()), StartsWith(Loc(path, long_horizon, "horizon_steps")));
  EXPECT_THAT(s.message(), HasSubstr("max_episode_steps"));

  const std::string two_kicks = absl::StrCat(
      "base_config: \"", RepoPath(kShipped), "\"\nplanner {\n  football { kick { cycles: 2 } }\n}\n");
  const std::string path2 = WriteTemp("football_two_kicks.textproto", two_kicks);
  c = LoadRunConfig(path2);
  ASSERT_TRUE(c.ok()) << c.status();
  s = ValidatePlannerConfig(*c);
  EXPECT_THAT(std::string(s.message()), StartsWith(Loc(path2, two_kicks, "cycles")));
}

}  // namespace
}  // namespace juggle::planner
