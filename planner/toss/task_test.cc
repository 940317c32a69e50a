// The toss throw as a planning task (planner/toss/task.h), found through the list of tasks
// (planner/tasks.cc) and driven by the generic receding-horizon driver: on the throw task
// without a base controller it throws well on every seed where zero action does not, with every
// visited state as predicted, bit for bit; it is deterministic for a seed and across thread
// counts; on the base controller, whose zero-residual throw is exact, it keeps the release
// exact; its shift is exact and its terms add up to its cost; and it refuses the toss runs it
// cannot plan, naming file, line and field.
#include "planner/toss/task.h"

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/outcomes.h"
#include "envs/toss/task_env.h"
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

constexpr char kShippedThrow[] = "configs/toss_throw_planner.textproto";

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

absl::StatusOr<LoadedConfig> LoadText(const std::string& name, const std::string& text) {
  return LoadRunConfig(WriteTemp(name, text));
}

// A config over the shipped toss planner config with `fields` added.
std::string Over(const std::string& fields) {
  return absl::StrCat("base_config: \"", RepoPath(kShippedThrow), "\"\n", fields, "\n");
}

// One throw episode: what it released and the actions that made it.
struct Throw {
  double velocity_error = 0, position_error = 0;
  int completions = 0;  // 1: a good throw (envs/toss/world.h, IsGoodThrow)
  Outcome end = Outcome::kRunning;
  std::vector<float> actions;
};

class TossTaskTest : public ::testing::Test {
 protected:
  void SetUp() override { Use(LoadRunConfig(RepoPath(kShippedThrow))); }

  void Use(absl::StatusOr<LoadedConfig> config) {
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *std::move(config);
    ASSERT_TRUE(ValidatePlannerConfig(config_).ok()) << ValidatePlannerConfig(config_);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
    // Through the list of tasks: the toss family's line in planner/tasks.cc.
    absl::StatusOr<std::shared_ptr<const PlanningTask>> task =
        MakePlanningTask(spec_, config_.run.planner());
    ASSERT_TRUE(task.ok()) << task.status();
    task_ = *task;
    ASSERT_EQ(task_->family(), "toss");
  }

  // Throws once from the start of env seed `seed`: with `planner`, or with zero action.
  Throw Run(uint64_t seed, RecedingHorizonPlanner* planner) {
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    AdaptiveWalk walk(&spec_->graph());
    env->Reset(walk);
    Throw t;
    float a[toss::kTossJoints] = {0, 0, 0, 0};
    for (int step = 0; step < 1000 && t.end == Outcome::kRunning; ++step) {
      if (planner != nullptr) {
        EXPECT_TRUE(planner->Act(*env, a).ok());
      }
      t.actions.insert(t.actions.end(), a, a + toss::kTossJoints);
      t.end = env->Step(a, walk).outcome;
    }
    const auto& task = static_cast<const toss::TossTaskEnv&>(*env);
    t.velocity_error = task.release_velocity_error();
    t.position_error = task.release_position_error();
    t.completions = task.completions();
    return t;
  }

  config::PlannerConfig Settings(uint64_t seed = 1) const {
    config::PlannerConfig p = config_.run.planner();
    p.set_seed(seed);
    return p;
  }

  LoadedConfig config_;
  std::shared_ptr<const EnvSpec> spec_;
  std::shared_ptr<const PlanningTask> task_;
};

TEST_F(TossTaskTest, ThrowsWellOnEverySeedWhereZeroActionDoesNotAndAsPredicted) {
  RolloutPool pool(spec_, 1);
  for (uint64_t seed : {11, 12, 13}) {
    SCOPED_TRACE(absl::StrCat("seed ", seed));
    const Throw zero = Run(seed, nullptr);
    RecedingHorizonPlanner planner(task_, Settings(), &pool, seed);
    const Throw planned = Run(seed, &planner);
    ASSERT_EQ(zero.end, toss::kReleased);
    ASSERT_EQ(planned.end, toss::kReleased);
    // Zero action holds the arm at home: the ball leaves at the start noise's speed.
    EXPECT_GT(zero.velocity_error, 2.0);
    EXPECT_EQ(zero.completions, 0);
    // The planner meets the schedule's velocity within a few cm/s at the home point, a good
    // throw (landing within the catch radius of the catching hand, on time).
    EXPECT_LT(planned.velocity_error, 0.05 * zero.velocity_error);
    EXPECT_LT(planned.position_error, 0.05);
    EXPECT_EQ(planned.completions, 1);
    EXPECT_GT(planner.totals().replans, 5);
    EXPECT_GT(planner.totals().prediction_checks, 20);
    EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  }
}

TEST_F(TossTaskTest, TheSameSeedGivesTheSameThrowOnAnyThreadCountAndAnotherSeedAnother) {
  RolloutPool one(spec_, 1), two(spec_, 2);
  RecedingHorizonPlanner a(task_, Settings(1), &one, 0), b(task_, Settings(1), &two, 0),
      c(task_, Settings(2), &one, 0);
  const Throw first = Run(21, &a);
  const Throw again = Run(21, &b);
  EXPECT_EQ(again.actions, first.actions);
  EXPECT_EQ(again.velocity_error, first.velocity_error);
  EXPECT_NE(Run(21, &c).actions, first.actions);
}

TEST_F(TossTaskTest, OnTheBaseControllerItKeepsTheExactReleaseExact) {
  Use(LoadText("toss_base_planner.textproto", Over("toss { base {} }")));
  RolloutPool pool(spec_, 1);
  for (uint64_t seed : {31, 32}) {
    SCOPED_TRACE(absl::StrCat("seed ", seed));
    // Zero residual: the base controller's release is exact to rounding (docs/results.md).
    const Throw zero = Run(seed, nullptr);
    EXPECT_LT(zero.velocity_error, 1e-9);
    EXPECT_LT(zero.position_error, 1e-9);
    RecedingHorizonPlanner planner(task_, Settings(), &pool, seed);
    const Throw planned = Run(seed, &planner);
    ASSERT_EQ(planned.end, toss::kReleased);
    EXPECT_LT(planned.velocity_error, 0.01);
    EXPECT_LT(planned.position_error, 0.002);
    EXPECT_EQ(planned.completions, 1);
    EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  }
}

TEST_F(TossTaskTest, AShiftedPlanActsExactlyAsTheOriginalAtTheSameStates) {
  const auto& task = static_cast<const TossThrowTask&>(*task_);
  const std::unique_ptr<Env> env = spec_->NewEnv(Rng(1));
  std::vector<double> theta(task.dim());
  for (size_t i = 0; i < theta.size(); ++i) theta[i] = 0.8 * std::sin(1.7 * i);
  const int knot = task.settings().knot_steps();
  const std::vector<double> shifted = task.Shift(theta, 2 * knot, 0);
  for (int s = 2 * knot; s <= (task.knots() - 1) * knot; ++s) {
    float a[toss::kTossJoints], b[toss::kTossJoints];
    task.Action(*env, theta.data(), {s, 0}, nullptr, a);
    task.Action(*env, shifted.data(), {s - 2 * knot, 0}, nullptr, b);
    for (int j = 0; j < toss::kTossJoints; ++j) EXPECT_EQ(a[j], b[j]) << "step " << s;
  }
  // The neck is not planned: its action is the prior's.
  const double prior[toss::kTossJoints] = {0.25, 0, 0, 0};
  float a[toss::kTossJoints];
  task.Action(*env, theta.data(), {0, 0}, prior, a);
  EXPECT_EQ(a[0], 0.25f);
  EXPECT_EQ(a[1], static_cast<float>(theta[0]));
}

TEST_F(TossTaskTest, ItsTermsAddUpToTheCostAndItsOutcomeIsTheRelease) {
  RolloutPool pool(spec_, 1);
  RecedingHorizonPlanner planner(task_, Settings(), &pool, 0);
  const std::unique_ptr<Env> env = spec_->NewEnv(Rng(41));
  AdaptiveWalk walk(&spec_->graph());
  env->Reset(walk);
  float a[toss::kTossJoints];
  ASSERT_TRUE(planner.Act(*env, a).ok());
  const ReplanReport& r = planner.last_replan();
  ASSERT_EQ(r.terms.size(), 4u);
  EXPECT_EQ(task_->term_names()[0], "release_velocity");
  EXPECT_NEAR(r.terms[0] + r.terms[1] + r.terms[2] + r.terms[3], r.best_cost,
              1e-9 * (1 + r.best_cost));
  EXPECT_EQ(r.terms[3], 0);  // released inside the horizon
  ASSERT_EQ(r.predicted_outcome.size(), 2u);
  const config::TossPlanning& s = config_.run.planner().toss();
  EXPECT_NEAR(r.terms[0],
              s.release_velocity() * std::pow(r.predicted_outcome[0] / s.velocity_scale(), 2),
              1e-9 * (1 + r.terms[0]));
  EXPECT_EQ(r.predicted_end, toss::kReleased);
  // A plan evaluated from the same state costs what the search found.
  absl::StatusOr<double> cost = planner.Evaluate(*env, planner.plan());
  ASSERT_TRUE(cost.ok());
  EXPECT_EQ(*cost, r.best_cost);
}

TEST(TossTaskConfigTest, ACatchTaskIsRefusedAtItsField) {
  const std::string catch_path = RepoPath("configs/toss_catch.textproto");
  absl::StatusOr<LoadedConfig> config = LoadText(
      "toss_catch_planner.textproto",
      absl::StrCat("base_config: \"", catch_path, "\"\nplanner { horizon_steps: 50 toss {} }\n"));
  ASSERT_TRUE(config.ok()) << config.status();
  const absl::Status s = ValidatePlannerConfig(*config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(Loc(catch_path, ReadText(catch_path), "task: CATCH")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("toss.task: the toss planning task plans the "
                                                  "THROW task (one throw per episode), not CATCH"));
}

TEST(TossTaskConfigTest, TheInLoopEnvIsRefusedAtItsField) {
  const std::string text = Over("toss { loop { pattern: \"3\" } base {} }");
  absl::StatusOr<LoadedConfig> config = LoadText("toss_loop_planner.textproto", text);
  ASSERT_TRUE(config.ok()) << config.status();
  const absl::Status s = ValidatePlannerConfig(*config);
  EXPECT_THAT(std::string(s.message()), StartsWith(Loc(config->config_path, text, "loop {")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("toss.loop: the toss planning task plans the "
                                                  "single-arm THROW task"));
}

TEST(TossTaskConfigTest, AHorizonThatCannotReachTheLatestReleaseIsRefused) {
  const std::string text = Over("planner { horizon_steps: 40 }");
  absl::StatusOr<LoadedConfig> config = LoadText("toss_short.textproto", text);
  ASSERT_TRUE(config.ok()) << config.status();
  const absl::Status s = ValidatePlannerConfig(*config);
  EXPECT_THAT(std::string(s.message()), StartsWith(Loc(config->config_path, text, "horizon_steps")));
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("planner.horizon_steps: a horizon of 40 control steps cannot reach the "
                        "latest release beat, 50 steps after an episode's start"));
  // Without the timing jitter the latest beat is 35 steps away.
  absl::StatusOr<LoadedConfig> steady = LoadText(
      "toss_steady.textproto",
      Over("planner { horizon_steps: 40 } toss { catch_timing_jitter_s: 0 }"));
  ASSERT_TRUE(steady.ok()) << steady.status();
  EXPECT_TRUE(ValidatePlannerConfig(*steady).ok()) << ValidatePlannerConfig(*steady);
}

// The toss plan's knots are its own (toss.knot_steps): the planner's whole-body knots asked of
// it would act nowhere, so they are refused at their field (PlanningTaskEntry::body_knots).
TEST(TossTaskConfigTest, WholeBodyKnotsAreRefusedAtTheirField) {
  const std::string text = Over("planner { body_knot_steps: 10 }");
  absl::StatusOr<LoadedConfig> config = LoadText("toss_body_knots.textproto", text);
  ASSERT_TRUE(config.ok()) << config.status();
  const absl::Status s = ValidatePlannerConfig(*config);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(Loc(config->config_path, text, "body_knot_steps")));
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("planner.body_knot_steps: the toss planning task's plan has no whole-body "
                        "knots"));
  absl::StatusOr<LoadedConfig> none =
      LoadText("toss_no_body_knots.textproto", Over("planner { body_knot_steps: 0 }"));
  ASSERT_TRUE(none.ok()) << none.status();
  EXPECT_TRUE(ValidatePlannerConfig(*none).ok()) << ValidatePlannerConfig(*none);
}

TEST(TossTaskConfigTest, AnOutOfRangeSettingIsAnErrorNamingFileLineAndField) {
  const std::string text = Over("planner { toss { knot_steps: 0 } }");
  const std::string path = WriteTemp("toss_knots.textproto", text);
  const absl::Status s = LoadRunConfig(path).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), StartsWith(Loc(path, text, "knot_steps: 0")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("planner.toss.knot_steps"));
}

}  // namespace
}  // namespace juggle::planner
