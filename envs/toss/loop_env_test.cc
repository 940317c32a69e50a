// In-loop training env: segments begin where the runtime puts the right arm in the task's mode,
// rewards are the task's, failures that are not the segment's own truncate, and the runtime
// restarts after a failed run. Partners here are zero-action policies (all-zero actor weights:
// tanh(0) = 0, the home pose), built without a trainer.
#include <cmath>
#include <memory>

#include "common/network_layout.h"
#include "envs/toss/outcomes.h"
#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/loop_env.h"

namespace juggle::toss {
namespace {

config::ExportedPolicy ZeroPolicy(const config::ModelConfig& model, int obs_dim) {
  std::vector<TensorSpec> layout = NetworkLayout(model, "actor", obs_dim, kTossJoints);
  layout.push_back({"actor.log_std", {kTossJoints}});
  int64_t n = 0;
  for (const TensorSpec& t : layout) n += t.numel();
  absl::StatusOr<FlatParameters> params =
      FlatParameters::Create(1, layout, std::vector<float>(n, 0.0f));
  EXPECT_TRUE(params.ok()) << params.status();
  config::ExportedPolicy exported;
  *exported.mutable_model() = model;
  exported.set_obs_dim(obs_dim);
  exported.set_act_dim(kTossJoints);
  exported.set_parameters(params->Serialize());
  exported.set_source("zero");
  return exported;
}

LoadedConfig LoopConfig(const std::string& task, const std::vector<std::string>& patterns) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/toss_" + task + ".textproto"));
  EXPECT_TRUE(config.ok()) << config.status();
  config::TossLoopConfig* loop = config->run.mutable_toss()->mutable_loop();
  for (const std::string& p : patterns) loop->add_pattern(p);
  loop->set_start_noise(0);
  *loop->mutable_catch_policy() = ZeroPolicy(config->run.model(), kTossCatchObs);
  *loop->mutable_throw_policy() = ZeroPolicy(config->run.model(), kTossThrowObs);
  return *config;
}

std::shared_ptr<const TossSpec> LoopSpec(const std::string& task,
                                         const std::vector<std::string>& patterns) {
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(LoopConfig(task, patterns));
  EXPECT_TRUE(spec.ok()) << spec.status();
  return *spec;
}

const float kZero[kTossJoints] = {0, 0, 0, 0};

TEST(TossLoopEnvTest, ThrowSegmentStartsHoldingABallAndEndsAtTheBeatWithTheReleaseReward) {
  std::shared_ptr<const TossSpec> spec = LoopSpec("throw", {"3"});
  std::unique_ptr<Env> env = spec->NewEnv(Rng(7));
  ASSERT_NE(dynamic_cast<TossLoopEnv*>(env.get()), nullptr) << "toss.loop makes a loop env";
  AdaptiveWalk walk(&spec->graph());
  env->Reset(walk);
  const TossJuggler& juggler = static_cast<TossLoopEnv&>(*env).juggler();
  EXPECT_TRUE(juggler.HoldsThrow(Hand::kRight));
  float obs[kTossThrowObs];
  env->WriteObservation(obs);
  // Pattern 3's first beat (right hand) is at 0.25 s; the run starts at t = 0.
  EXPECT_NEAR(obs[kTossCatchObs], 0.25, 1e-6) << "t_throw";
  const ThrowTiming three = ComputeThrowTiming(3, 0, spec->timing());
  EXPECT_NEAR(obs[kTossCatchObs + 1], three.v_x, 1e-6);
  EXPECT_NEAR(obs[kTossCatchObs + 2], three.v_z, 1e-6);

  StepResult r;
  double effort_reward = 0;
  while ((r = env->Step(kZero, walk)).outcome == Outcome::kRunning) {
    effort_reward += r.reward;
  }
  EXPECT_EQ(r.outcome, kReleased);
  EXPECT_EQ(env->steps(), 25);
  // The resting hand releases at home with (almost) zero velocity: the terminal reward is
  // −w5·|v̄|², v̄ from Eq. 2–3, up to the effort of one step.
  const double expected = -spec->toss().w_release_velocity() * (three.v_x * three.v_x + three.v_z * three.v_z);
  EXPECT_NEAR(r.reward, expected, 0.05);
  EXPECT_LE(effort_reward, 0);
  EXPECT_EQ(env->completions(), 0) << "a ball released at rest is not a good throw";
}

TEST(TossLoopEnvTest, CatchSegmentCatchesTheScheduledBallIntoTheRestingHand) {
  // The initial balls of 3 fly on the schedule's parabolas, so the first ball due at the right
  // hand comes down onto its home point: the resting hand catches it at home height.
  std::shared_ptr<const TossSpec> spec = LoopSpec("catch", {"3"});
  std::unique_ptr<Env> env = spec->NewEnv(Rng(7));
  AdaptiveWalk walk(&spec->graph());
  env->Reset(walk);
  const TossLoopEnv& loop = static_cast<TossLoopEnv&>(*env);
  EXPECT_LT(loop.juggler().world().held_by(Hand::kRight), 0) << "catch mode: the hand is empty";
  StepResult r;
  while ((r = env->Step(kZero, walk)).outcome == Outcome::kRunning) {
  }
  EXPECT_EQ(r.outcome, kCaught);
  EXPECT_EQ(env->completions(), 1);
  EXPECT_GT(r.reward, -0.1) << "caught within a few cm of hand_z, little effort";
  EXPECT_EQ(loop.runs_started(), 1);
}

TEST(TossLoopEnvTest, AHandThatMovesAwayDropsItsBallAndTheRunRestarts) {
  // The arm swings away from its home point, so the balls due at the right hand fall past it:
  // the segment's own failure (−w2), and the runtime starts a new run for the next episode.
  // Pattern 4: every ball a hand throws comes back to it, so the first ball to fall (the one the
  // partner released at rest) is the right hand's too.
  std::shared_ptr<const TossSpec> spec = LoopSpec("catch", {"4"});
  std::unique_ptr<Env> env = spec->NewEnv(Rng(11));
  AdaptiveWalk walk(&spec->graph());
  const TossLoopEnv& loop = static_cast<TossLoopEnv&>(*env);
  const float away[kTossJoints] = {0, 1, 1, 0};
  for (int episode = 0; episode < 3; ++episode) {
    env->Reset(walk);
    EXPECT_EQ(loop.runs_started(), episode + 1);
    StepResult r;
    while ((r = env->Step(away, walk)).outcome == Outcome::kRunning) {
    }
    EXPECT_EQ(r.outcome, kDropped);
    EXPECT_NEAR(r.reward, -spec->toss().w_catch_height(), 0.1);
    EXPECT_EQ(env->completions(), 0);
    EXPECT_TRUE(loop.juggler().over());
  }
}

TEST(TossLoopEnvTest, SameRngGivesTheSameEpisodes) {
  std::shared_ptr<const TossSpec> spec = LoopSpec("throw", {"3", "531", "4"});
  std::unique_ptr<Env> a = spec->NewEnv(Rng(5)), b = spec->NewEnv(Rng(5));
  AdaptiveWalk walk(&spec->graph());
  const float action[kTossJoints] = {0.1f, -0.2f, 0.3f, 0.0f};
  for (int episode = 0; episode < 6; ++episode) {
    a->Reset(walk);
    b->Reset(walk);
    StepResult ra, rb;
    do {
      ra = a->Step(action, walk);
      rb = b->Step(action, walk);
      ASSERT_EQ(ra.reward, rb.reward);
    } while (ra.outcome == Outcome::kRunning && rb.outcome == Outcome::kRunning);
    EXPECT_EQ(ra.outcome, rb.outcome);
    EXPECT_EQ(a->steps(), b->steps());
  }
}

TEST(TossLoopEnvTest, PatternWithoutARightHandThrowIsRejected) {
  // The right hand throws on even beats: "04" gives it only the 0s, "40" the 4s.
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec =
      TossSpec::Create(LoopConfig("throw", {"04"}));
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(spec.status().message().find("pattern"), std::string::npos) << spec.status();
  EXPECT_NE(spec.status().message().find("never gives the right hand a throw"), std::string::npos)
      << spec.status();
  EXPECT_TRUE(TossSpec::Create(LoopConfig("throw", {"40"})).ok());
}

TEST(TossLoopEnvTest, PartnerPolicyOfTheWrongTaskIsRejected) {
  LoadedConfig config = LoopConfig("throw", {"3"});
  // The throw partner slot gets a catch-sized policy.
  *config.run.mutable_toss()->mutable_loop()->mutable_throw_policy() =
      ZeroPolicy(config.run.model(), kTossCatchObs);
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(config);
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(spec.status().message().find("throw_policy_file"), std::string::npos) << spec.status();
}

}  // namespace
}  // namespace juggle::toss
