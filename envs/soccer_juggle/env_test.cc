// Behaviour of one soccer-juggling environment.
#include "envs/soccer_juggle/env.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "gtest/gtest.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"

namespace juggle::soccer_juggle {
namespace {



constexpr float kZeroAction[kNumActions] = {0};

class JuggleEnvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = testing::LoadSpec("right_foot");
    ASSERT_NE(spec_, nullptr);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    env_ = std::make_unique<JuggleEnv>(spec_, Rng(11));
    down_ = *spec_->graph().FindNode("right_foot_down");
  }
  // Moves the ball (at rest) to a world position and refreshes derived quantities.
  void PlaceBall(double x, double y, double z) {
    mjData* d = env_->data();
    double* b = d->qpos + spec_->ball_qpos();
    b[0] = x; b[1] = y; b[2] = z;
    mju_zero(d->qvel + spec_->ball_dof(), 6);
    mj_forward(spec_->model(), d);
  }
  const double* BodyPos(const char* name) {
    return env_->data()->xpos + 3 * mj_name2id(spec_->model(), mjOBJ_BODY, name);
  }

  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  std::unique_ptr<JuggleEnv> env_;
  int down_ = -1;
};

TEST_F(JuggleEnvTest, ObservationHas88PlusThreeOneHotsAndActionHas28) {
  EXPECT_EQ(spec_->obs_dim(), 88 + 3 * spec_->graph().num_nodes());
  EXPECT_EQ(kNumActions, 28);
  env_->ResetAt(down_, *walk_);
  std::vector<float> obs(spec_->obs_dim());
  env_->WriteObservation(obs.data());
  // One-hots: exactly one 1 in each of the three blocks, at current / next / next-next.
  const int n = spec_->graph().num_nodes();
  for (int block = 0; block < 3; ++block) {
    float sum = 0;
    for (int i = 0; i < n; ++i) sum += obs[kObsBase + block * n + i];
    EXPECT_EQ(sum, 1.0f);
  }
  EXPECT_EQ(obs[kObsBase + down_], 1.0f);
  EXPECT_FLOAT_EQ(obs[0], static_cast<float>(spec_->env().root_height()));
}

TEST_F(JuggleEnvTest, ResetPutsCharacterAtReferencePoseAndBallAtItsApexAtRest) {
  env_->ResetAt(down_, *walk_);
  const mjData* d = env_->data();
  const double* ball = d->qpos + spec_->ball_qpos();
  const config::NodeSpec& node = spec_->graph().node(down_).spec;
  EXPECT_NEAR(ball[2], node.apex_height(), 1e-9);
  EXPECT_NEAR(ball[0] - d->qpos[0], node.ball_target().x(), 1e-9);
  EXPECT_NEAR(ball[1] - d->qpos[1], node.ball_target().y(), 1e-9);
  for (int i = 0; i < spec_->model()->nv; ++i) EXPECT_EQ(d->qvel[i], 0.0);
  for (int i = 0; i < kCharacterNq; ++i) EXPECT_EQ(d->qpos[i], env_->reference_pose()[i]);
}

TEST_F(JuggleEnvTest, ZeroActionRolloutStaysUprightForOneSecond) {
  env_->ResetAt(down_, *walk_);
  PlaceBall(0.6, -0.1, 40.0);  // ball out of play: only falling can end the episode
  const int steps = static_cast<int>(std::round(1.0 / spec_->control_dt()));
  for (int i = 0; i < steps; ++i) {
    const StepResult r = env_->Step(kZeroAction, *walk_);
    ASSERT_EQ(r.outcome, Outcome::kRunning) << "step " << i << ": " << OutcomeName(spec_->outcome_names(), r.outcome);
    PlaceBall(env_->data()->qpos[0] + 0.6, env_->data()->qpos[1] - 0.1, 40.0);
  }
  EXPECT_GT(env_->data()->qpos[2], 0.8);
}

TEST_F(JuggleEnvTest, BallOnHeadIsADisallowedContactInAFootNode) {
  env_->ResetAt(down_, *walk_);
  const double* head = BodyPos("neck");
  PlaceBall(head[0], head[1], head[2] + 0.175 + 0.1025 + 0.11 + 0.005);
  Outcome outcome = Outcome::kRunning;
  for (int i = 0; i < 20 && outcome == Outcome::kRunning; ++i) {
    outcome = env_->Step(kZeroAction, *walk_).outcome;
  }
  EXPECT_EQ(outcome, kBadContact);
}

TEST_F(JuggleEnvTest, BallOnFloorIsADisallowedContact) {
  env_->ResetAt(down_, *walk_);
  PlaceBall(env_->data()->qpos[0] + 0.6, -0.1, 0.109);  // 1 mm into the floor
  EXPECT_EQ(env_->Step(kZeroAction, *walk_).outcome, kBadContact);
}

TEST_F(JuggleEnvTest, FootContactLongBeforeTheWindowTerminatesForTiming) {
  env_->ResetAt(down_, *walk_);
  // Phase 0: the nominal contact is ~0.43 s away, far outside the ±0.06 s window. Rest the
  // ball on the right foot so it touches it at once.
  const int foot_geom = mj_name2id(spec_->model(), mjOBJ_GEOM, "right_foot");
  const double* g = env_->data()->geom_xpos + 3 * foot_geom;
  PlaceBall(g[0], g[1], g[2] + 0.0275 + 0.11 - 0.002);
  EXPECT_EQ(env_->Step(kZeroAction, *walk_).outcome, kContactTiming);
}

TEST_F(JuggleEnvTest, FootContactInsideTheWindowIsAllowed) {
  env_->ResetAt(down_, *walk_);
  // Run the reference until the step before the contact, holding the ball out of play.
  const double dt = spec_->control_dt();
  while (spec_->cursor().SecondsFromContact(env_->cursor(), env_->cursor().phase) < -dt) {
    ASSERT_EQ(env_->Step(kZeroAction, *walk_).outcome, Outcome::kRunning);
    PlaceBall(env_->data()->qpos[0] + 0.6, -0.1, 40.0);
  }
  const int foot_geom = mj_name2id(spec_->model(), mjOBJ_GEOM, "right_foot");
  const double* g = env_->data()->geom_xpos + 3 * foot_geom;
  PlaceBall(g[0], g[1], g[2] + 0.0275 + 0.11 - 0.002);
  const Outcome o = env_->Step(kZeroAction, *walk_).outcome;
  EXPECT_TRUE(o == Outcome::kRunning || o == kBallLost) << OutcomeName(spec_->outcome_names(), o);
}

TEST_F(JuggleEnvTest, NonFiniteStateEndsTheEpisodeAsDivergedWithFiniteObservation) {
  env_->ResetAt(down_, *walk_);
  env_->data()->qvel[10] = std::numeric_limits<double>::quiet_NaN();
  const StepResult r = env_->Step(kZeroAction, *walk_);
  EXPECT_EQ(r.outcome, Outcome::kDiverged);
  EXPECT_TRUE(r.terminated());
  EXPECT_TRUE(std::isfinite(r.reward));
  std::vector<float> obs(spec_->obs_dim());
  env_->WriteObservation(obs.data());
  for (float v : obs) EXPECT_TRUE(std::isfinite(v));
}

TEST_F(JuggleEnvTest, ConstantBallForceAcceleratesTheBallByForceOverMass) {
  LoadedConfig config = spec_->config();
  config.run.mutable_soccer_juggle()->mutable_env()->mutable_ball_force()->set_x(1.0);
  auto pushed = JuggleSpec::Create(config);
  ASSERT_TRUE(pushed.ok()) << pushed.status();
  JuggleEnv env(*pushed, Rng(3));
  env.ResetAt(down_, *walk_);
  const double x0 = env.data()->qpos[spec_->ball_qpos()] - env.data()->qpos[0];
  const int steps = 10;
  for (int i = 0; i < steps; ++i) ASSERT_EQ(env.Step(kZeroAction, *walk_).outcome, Outcome::kRunning);
  const double t = steps * spec_->control_dt();
  const double dx = env.data()->qpos[spec_->ball_qpos()] - x0;  // root x barely moves
  EXPECT_NEAR(dx, 0.5 * (1.0 / 0.45) * t * t, 0.01);
}

TEST_F(JuggleEnvTest, TimeLimitTruncatesWithoutFailing) {
  LoadedConfig config = spec_->config();
  config.run.mutable_soccer_juggle()->mutable_env()->set_max_episode_steps(5);
  auto short_spec = JuggleSpec::Create(config);
  ASSERT_TRUE(short_spec.ok());
  JuggleEnv env(*short_spec, Rng(3));
  env.ResetAt(down_, *walk_);
  StepResult r;
  for (int i = 0; i < 5; ++i) r = env.Step(kZeroAction, *walk_);
  EXPECT_EQ(r.outcome, Outcome::kTimeLimit);
  EXPECT_TRUE(r.truncated());
  EXPECT_FALSE(r.terminated());
  for (const EdgeEvent& e : env.events()) EXPECT_NE(e.type, EdgeEventType::kFailed);
}

TEST_F(JuggleEnvTest, RewardIsAtMostPointOneAndNearItOnTheReference) {
  env_->ResetAt(down_, *walk_);
  const StepResult r = env_->Step(kZeroAction, *walk_);
  EXPECT_LE(r.reward, 0.1f + 1e-6f);
  EXPECT_GT(r.reward, 0.08f);
}

}  // namespace
}  // namespace juggle::soccer_juggle
