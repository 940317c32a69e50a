// The reward's contract (reward.h) on real steps of the recipe's env: its numbered terms add up
// to exactly the reward Step returns, terms 1-4 are the tracking of the step's start reference,
// and term 5 is paid once per kick, at its release.
#include "envs/soccer_juggle/reward.h"

#include <limits>
#include <memory>
#include <vector>

#include "common/adaptive_walk.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

// Zero action with the recipe's base controller: it kicks, and its kick term is on (w_kick 1).
class RewardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = testing::LoadSpec("right_foot_recipe");
    ASSERT_NE(spec_, nullptr);
    ASSERT_GT(spec_->env().reward().w_kick(), 0);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(RewardTest, TermsAddUpToTheStepRewardAndTrackTheStepsStartReference) {
  const config::RewardConfig& w = spec_->env().reward();
  const float zero[kNumActions] = {0};
  int steps = 0, kicks = 0;
  for (uint64_t episode = 0; episode < 20; ++episode) {
    JuggleEnv env(spec_, Rng::ForStream(1, 0, episode));
    env.Reset(*walk_);
    EXPECT_EQ(env.state().reward.Total(), 0.0f) << "no step yet";
    // Each cycle's kick is paid at most once; count the payments since the last DOWN node.
    int paid_this_cycle = 0;
    StepResult r;
    do {
      const CursorState before = env.cursor();
      r = env.Step(zero, *walk_);
      ++steps;
      const RewardTerms& t = env.state().reward;
      // The contract, written out: float(scale·(1 + 2 + 3 + 4)) + 5.
      const float sum =
          static_cast<float>(w.scale() * (t.position + t.orientation + t.joint + t.ball)) + t.kick;
      ASSERT_EQ(r.reward, sum) << "step " << env.steps();
      ASSERT_EQ(t.scale, w.scale());
      // Terms 1-4: the post-step state against the reference of the step's start.
      const RewardTerms tracking = TrackingReward(
          *spec_, *env.data(), env.reference_pose(),
          spec_->cursor().DesiredBall(before, before.phase));
      EXPECT_EQ(t.position, tracking.position);
      EXPECT_EQ(t.orientation, tracking.orientation);
      EXPECT_EQ(t.joint, tracking.joint);
      EXPECT_EQ(t.ball, tracking.ball);
      EXPECT_GT(t.position, 0);
      EXPECT_LE(t.position, w.w_position());
      EXPECT_LE(t.orientation, w.w_orientation());
      EXPECT_LE(t.joint, w.w_joint());
      EXPECT_LE(t.ball, w.w_ball());
      // Term 5: only at a release (touched before, off the body now, going up).
      if (env.cursor().current != before.current &&
          spec_->graph().node(env.cursor().current).stage == config::DOWN) {
        paid_this_cycle = 0;
      }
      if (t.kick != 0) {
        ++kicks;
        ++paid_this_cycle;
        EXPECT_EQ(r.outcome, Outcome::kRunning);
        EXPECT_TRUE(env.state().kick_touched && !env.state().touched_this_step);
        EXPECT_GT(env.data()->qvel[spec_->ball_dof() + 2], 0);
        EXPECT_GT(t.kick, 0);
        EXPECT_LE(t.kick, w.w_kick());
        EXPECT_LE(paid_this_cycle, 1);
      }
    } while (r.outcome == Outcome::kRunning);
  }
  EXPECT_GT(steps, 200);
  EXPECT_GE(kicks, 5) << "the base controller kicks in most of 20 episodes";
}

TEST_F(RewardTest, ADivergedStepEarnsNothing) {
  JuggleEnv env(spec_, Rng(3));
  env.Reset(*walk_);
  env.data()->qvel[10] = std::numeric_limits<double>::quiet_NaN();
  const StepResult r = env.Step(std::vector<float>(kNumActions, 0.0f).data(), *walk_);
  ASSERT_EQ(r.outcome, Outcome::kDiverged);
  EXPECT_EQ(r.reward, 0.0f);
  const RewardTerms& t = env.state().reward;
  EXPECT_EQ(t.position + t.orientation + t.joint + t.ball + t.kick, 0.0);
}

}  // namespace
}  // namespace juggle::soccer_juggle
