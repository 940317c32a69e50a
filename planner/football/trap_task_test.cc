// Football's trap as a planning task (planner/football/trap_task.h), found through the list of
// tasks and driven by the generic receding-horizon driver: on lobs to the foot it meets the
// ball with the foot first where standing still meets it with the shin, with every visited
// state as predicted, bit for bit; its actions replayed as plain actions in a fresh env give the same trap; it is
// deterministic for a seed across thread counts; its terms add up to its cost; the reach pose
// holds the standing pose before its ramp and moves the named joints after it.
#include "planner/football/trap_task.h"

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

using ::juggle::testing::RepoPath;

constexpr char kShipped[] = "configs/football_trap.textproto";
// Two lobs to the foot (env seeds Rng(s); the shipped settings were chosen on juggle eval's
// seed 1000000, other streams).
constexpr uint64_t kSeeds[] = {1000001, 1000017};

// One trap episode: how it ended, its metrics and the actions that made it.
struct Trap {
  Outcome end = Outcome::kRunning;
  std::vector<float> actions;
  std::vector<double> final_qpos;
};

class FootballTrapTaskTest : public ::testing::Test {
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
    ASSERT_EQ(task_->dim(), kTrapVariables);
  }

  // Traps once from the start of env seed `seed`: with `planner`, with `replay`'s actions, or
  // with zero action.
  Trap Run(uint64_t seed, RecedingHorizonPlanner* planner, const std::vector<float>* replay = nullptr) {
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    Trap k;
    std::vector<float> a(spec_->act_dim(), 0.0f);
    for (int step = 0; step < 1000 && k.end == Outcome::kRunning; ++step) {
      if (planner != nullptr) {
        EXPECT_TRUE(planner->Act(*env, a.data()).ok());
      }
      if (replay != nullptr) std::copy_n(replay->begin() + step * a.size(), a.size(), a.begin());
      k.actions.insert(k.actions.end(), a.begin(), a.end());
      k.end = env->Step(a.data(), *walk_).outcome;
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

TEST_F(FootballTrapTaskTest, MeetsALobWithTheFootWhereStandingStillDoesNotAndAsPredicted) {
  RolloutPool pool(spec_, 2);
  for (uint64_t seed : kSeeds) {
    SCOPED_TRACE(absl::StrCat("seed ", seed));
    {
      const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
      env->Reset(*walk_);
      const football::TrapEpisode& e = static_cast<const football::FootballEnv&>(*env).state().trap;
      ASSERT_EQ(e.part, config::FOOT);
      ASSERT_EQ(e.pass.kind, football::PassKind::kLob);
    }
    // Standing still, another part (the shin) meets the ball first.
    EXPECT_EQ(Run(seed, nullptr).end, football::kWrongPart);
    RecedingHorizonPlanner planner(task_, Settings(), &pool, seed);
    const Trap planned = Run(seed, &planner);
    // The foot first, before the turf (kTrapped), and standing at the end.
    EXPECT_EQ(planned.end, football::kTrapped);
    EXPECT_GT(planner.totals().prediction_checks, 10);
    EXPECT_EQ(planner.totals().prediction_mismatches, 0);
    // The plan's actions replayed without the planner: the same trap, bit for bit.
    const Trap replayed = Run(seed, nullptr, &planned.actions);
    EXPECT_EQ(replayed.final_qpos, planned.final_qpos);
    EXPECT_EQ(replayed.end, planned.end);
  }
}

TEST_F(FootballTrapTaskTest, TheSameSeedGivesTheSameTrapOnAnyThreadCountAndAnotherSeedAnother) {
  config::PlannerConfig small = Settings(1);
  small.set_samples(6);
  small.set_iterations(2);
  RolloutPool one(spec_, 1), two(spec_, 2);
  RecedingHorizonPlanner a(task_, small, &one, 0), b(task_, small, &two, 0);
  config::PlannerConfig other = small;
  other.set_seed(2);
  RecedingHorizonPlanner c(task_, other, &one, 0);
  const Trap first = Run(kSeeds[0], &a);
  EXPECT_EQ(Run(kSeeds[0], &b).actions, first.actions);
  EXPECT_NE(Run(kSeeds[0], &c).actions, first.actions);
}

TEST_F(FootballTrapTaskTest, TheTermsAddUpToTheCost) {
  const std::unique_ptr<Env> env = spec_->NewEnv(Rng(3));
  env->Reset(*walk_);
  std::vector<double> theta(task_->dim(), 0.0);
  theta[1] = 0.4;  // hip flexion
  std::unique_ptr<RolloutScorer> scorer = task_->NewScorer();
  scorer->Begin(*env);
  std::vector<float> a(spec_->act_dim());
  StepResult r;
  for (int step = 0; step < 80 && r.outcome == Outcome::kRunning; ++step) {
    task_->Action(*env, theta.data(), {step, 0}, nullptr, a.data());
    r = env->Step(a.data(), *walk_);
    scorer->AfterStep(*env, a.data(), r);
  }
  const double total = scorer->Finish(*env);
  double sum = 0;
  for (double t : scorer->terms()) sum += t;
  EXPECT_GT(total, 0);
  EXPECT_NEAR(sum, total, 1e-9 * std::max(1.0, total));
  EXPECT_EQ(scorer->terms().size(), task_->term_names().size());
}

TEST_F(FootballTrapTaskTest, TheReachPoseIsStandingBeforeItsRampAndMovesTheNamedJointsAfter) {
  const auto& spec = static_cast<const football::FootballSpec&>(*spec_);
  const double theta[kTrapVariables] = {0.05, 0.4, 0.1, 0.3, -0.2, 0.2, 0.1, 0.3, 0.5};
  humanoid::CharacterPose before, after;
  TrapReachPose(spec, theta, 1.0, 1.0 + 0.05 - 0.3 - 1e-6, 0.3, &before);
  EXPECT_EQ(before, spec.standing_pose());
  // Reached at 1.05 s; given back by half 0.3 s later.
  TrapReachPose(spec, theta, 1.0, 1.05, 0.3, &after);
  const humanoid::Joints& joints = spec.joints();
  EXPECT_DOUBLE_EQ(after[joints[humanoid::kRightKnee].qpos_adr], -0.3);
  humanoid::CharacterPose given;
  TrapReachPose(spec, theta, 1.0, 1.35 + 1e-9, 0.3, &given);
  EXPECT_NEAR(given[joints[humanoid::kRightKnee].qpos_adr], -0.15, 1e-6);
  for (humanoid::JointId j : {humanoid::kRightHip, humanoid::kRightAnkle, humanoid::kChest,
                              humanoid::kNeck}) {
    EXPECT_NE(after[joints[j].qpos_adr], before[joints[j].qpos_adr]) << j;
  }
  EXPECT_EQ(after[joints[humanoid::kLeftKnee].qpos_adr], before[joints[humanoid::kLeftKnee].qpos_adr]);
}

}  // namespace
}  // namespace juggle::planner
