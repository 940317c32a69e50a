// The planner's stall (PlannerCost.stall, docs/planner.md "Stalls"): the stall term on a
// hand-made state against its formula, which touches are a catch or a hold rather than a kick,
// and a rollout through a stall that scores its stall steps and no kick.
#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "common/adaptive_walk.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/soccer_juggle/cost.h"
#include "planner/planner_config.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

// configs/stall_planner.textproto with `graph` (a repository path) and no start noise.
std::shared_ptr<const JuggleSpec> StallSpec(LoadedConfig* config,
                                            const std::string& graph =
                                                "configs/graphs/right_foot_stall.textproto") {
  const std::string run = ::juggle::testing::WriteTemp(
      "run.textproto",
      absl::StrCat(
          "base_config: \"", ::juggle::testing::RepoPath("configs/stall_planner.textproto"),
          "\"\nname: \"t\"\nsoccer_juggle { graph_file: \"", ::juggle::testing::RepoPath(graph),
          "\" env { start { ball_position: 0 ball_velocity: 0 joint_angle: 0 "
          "joint_speed: 0 random_phase_fraction: 0 } } }\n"));
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(run);
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  *config = *loaded;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return std::dynamic_pointer_cast<const JuggleSpec>(*spec);
}

class StallTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = StallSpec(&config_);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    cost_ = config_.run.planner().soccer_juggle().cost();
  }
  // An episode started in node `name` (its reference pose, the ball at its reference).
  std::unique_ptr<JuggleEnv> StartIn(const std::string& name) const {
    auto env = std::make_unique<JuggleEnv>(spec_, Rng(5));
    env->ResetAt(*spec_->graph().FindNode(name), *walk_);
    return env;
  }
  // Moves the ball by `dp` (m) and gives it velocity `v` (m/s).
  void MoveBall(JuggleEnv* env, const double dp[3], const double v[3]) const {
    mjData* d = env->data();
    for (int c = 0; c < 3; ++c) {
      d->qpos[spec_->ball_qpos() + c] += dp[c];
      d->qvel[spec_->ball_dof() + c] = v[c];
    }
    mj_forward(spec_->model(), d);
  }

  LoadedConfig config_;
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  config::PlannerCost cost_;
};

TEST_F(StallTest, TheStallTermIsZeroForABallAtRestWhereTheStallHoldsIt) {
  std::unique_ptr<JuggleEnv> env = StartIn("right_foot_stall");
  const double* ball = env->data()->qpos + spec_->ball_qpos();
  // The start puts the ball at the node's stall position: 0.655 m ahead of the root, 0.1 m to
  // its right, 0.4 m up (graphs/right_foot_stall.textproto).
  EXPECT_NEAR(ball[0] - env->data()->qpos[0], 0.655, 1e-12);
  EXPECT_NEAR(ball[1] - env->data()->qpos[1], -0.1, 1e-12);
  EXPECT_NEAR(ball[2], 0.4, 1e-12);
  EXPECT_EQ(StallCost(*env, cost_), 0.0);
}

TEST_F(StallTest, TheStallTermWeighsTheBallsOffsetAndSpeedByTheirScales) {
  std::unique_ptr<JuggleEnv> env = StartIn("right_foot_stall");
  // 5 cm off (3-4-0) and 0.5 m/s (0.3, 0, -0.4): at the default scales (0.05 m, 0.5 m/s) each
  // part is 1, so the term is the weight (10) times 2.
  const double dp[3] = {0.03, 0.04, 0}, v[3] = {0.3, 0, -0.4};
  MoveBall(env.get(), dp, v);
  ASSERT_EQ(cost_.stall(), 10);
  ASSERT_EQ(cost_.stall_scale(), 0.05);
  ASSERT_EQ(cost_.stall_speed_scale(), 0.5);
  EXPECT_NEAR(StallCost(*env, cost_), 20.0, 1e-9);
  // Halving the scales quadruples it.
  config::PlannerCost tight = cost_;
  tight.set_stall_scale(0.025);
  tight.set_stall_speed_scale(0.25);
  EXPECT_NEAR(StallCost(*env, tight), 80.0, 1e-9);
}

TEST_F(StallTest, TheStallTermIsZeroOutsideAStallNode) {
  std::unique_ptr<JuggleEnv> env = StartIn("right_foot_up");
  const double dp[3] = {0.03, 0.04, 0}, v[3] = {0.3, 0, -0.4};
  MoveBall(env.get(), dp, v);
  EXPECT_EQ(StallCost(*env, cost_), 0.0);
}

TEST_F(StallTest, TouchesInAStallAndInTheDownNodeBeforeItAreNotKicks) {
  EXPECT_TRUE(InStall(*StartIn("right_foot_stall")));
  EXPECT_TRUE(InStall(*StartIn("right_foot_stall_exit")));
  EXPECT_FALSE(InStall(*StartIn("right_foot_up")));
  // A DOWN node is a stall's catch when its sampled next node is the stall (the catch node of
  // the stall-only graph), and a kick's otherwise (the juggle's graph without stalls).
  LoadedConfig other;
  std::shared_ptr<const JuggleSpec> to_stall = StallSpec(&other, "configs/graphs/right_foot_stall_only.textproto");
  JuggleEnv catching(to_stall, Rng(5));
  AdaptiveWalk walk(&to_stall->graph());
  catching.ResetAt(*to_stall->graph().FindNode("right_foot_catch"), walk);
  EXPECT_TRUE(InStall(catching));
  std::shared_ptr<const JuggleSpec> juggle =
      StallSpec(&other, "configs/graphs/right_foot_smooth.textproto");
  JuggleEnv kicking(juggle, Rng(5));
  AdaptiveWalk juggle_walk(&juggle->graph());
  kicking.ResetAt(*juggle->graph().FindNode("right_foot_down"), juggle_walk);
  EXPECT_FALSE(InStall(kicking));
}

TEST_F(StallTest, ARolloutScoresAStallsStepsAndNoKickUntilTheBallLeavesTheFootFromUp) {
  // The ball dropped onto the held foot from 7 cm above its stall position (where it rests once
  // the raised leg has sagged under it): it lands and hops on the foot; none of that is a kick.
  std::unique_ptr<JuggleEnv> env = StartIn("right_foot_stall");
  const double dp[3] = {0, 0, 0.07}, v[3] = {0, 0, 0};
  MoveBall(env.get(), dp, v);
  constexpr int kHorizon = 60;
  SoccerRolloutScorer scorer(cost_, kHorizon, /*run_on_every_kick=*/false);
  scorer.Begin(*env);
  const float zero[kNumActions] = {0};
  double stall_sum = 0;
  bool left_the_foot = false;
  int t = 0;
  // Until the walk takes the stall's exit into right_foot_up (the self-loop weighs 30, the exit
  // 1).
  for (; t < kHorizon && InStall(*env); ++t) {
    const StepResult r = env->Step(zero, *walk_);
    ASSERT_EQ(r.outcome, Outcome::kRunning) << "step " << t;
    if (InStall(*env)) {
      left_the_foot |= env->state().kick_touched && !env->state().touched_this_step;
      EXPECT_FALSE(scorer.RunsOn(*env)) << "a held ball is no kick to run on to, step " << t;
    }
    scorer.AfterStep(*env, zero, r);
    stall_sum += StallCost(*env, cost_);  // the formula at each state, summed independently
  }
  ASSERT_FALSE(InStall(*env)) << "the stall should end inside the horizon";
  EXPECT_GE(t, 8);
  EXPECT_TRUE(left_the_foot) << "the drop should make the ball hop off the foot";
  EXPECT_EQ(scorer.kicks(), 0);
  // In right_foot_up the ball is sent up by hand (4 m/s): its release is the cycle's kick.
  mjData* d = env->data();
  d->qvel[spec_->ball_dof() + 2] = 4.0;
  mj_forward(spec_->model(), d);
  for (int k = 0; k < 5 && scorer.kicks() == 0; ++k, ++t) {
    const StepResult r = env->Step(zero, *walk_);
    ASSERT_EQ(r.outcome, Outcome::kRunning) << "step " << t;
    scorer.AfterStep(*env, zero, r);
    stall_sum += StallCost(*env, cost_);
  }
  scorer.Finish(*env);
  EXPECT_EQ(scorer.kicks(), 1) << "the ball's release from right_foot_up is scored";
  EXPECT_FALSE(scorer.first_outcome().empty());
  const std::vector<double> terms = scorer.terms();
  ASSERT_EQ(terms.size(), SoccerTermNames().size());
  ASSERT_EQ(SoccerTermNames()[8], "stall");
  EXPECT_GT(stall_sum, 0);
  EXPECT_NEAR(terms[8], stall_sum / kHorizon, 1e-9 * stall_sum);
  EXPECT_GT(terms[2], 0.0) << "kick term";
}

TEST(StallConfigTest, TheShippedStallPlannerPassesThePlannersLoadChecks) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(::juggle::testing::RepoPath("configs/stall_planner.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_TRUE(ValidatePlannerConfig(*config).ok()) << ValidatePlannerConfig(*config);
}

}  // namespace
}  // namespace juggle::planner
