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

class JuggleEnvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = testing::LoadSpec("right_foot_paper");  // no start variation: exact starts
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
  // The fixture's spec with every node's leg swing shaped by `profile` (null on failure, with
  // the test failed).
  std::shared_ptr<const JuggleSpec> SpecWithSwingProfile(config::SwingProfile profile) {
    return SpecWithSwing([profile](config::LegSwing* swing) { swing->set_profile(profile); });
  }
  // The fixture's spec with every node's leg swing changed by `change`.
  template <typename Change>
  std::shared_ptr<const JuggleSpec> SpecWithSwing(Change change) {
    LoadedConfig config = spec_->config();
    config::ControlGraph* graph = config.run.mutable_soccer_juggle()->mutable_graph();
    for (config::NodeSpec& node : *graph->mutable_node()) {
      change(node.mutable_pose()->mutable_leg_swing());
    }
    absl::StatusOr<ControlGraph> built = ControlGraph::Build(*graph, config.graph_locator);
    EXPECT_TRUE(built.ok()) << built.status();
    if (!built.ok()) return nullptr;
    config.graph = std::make_shared<const ControlGraph>(*std::move(built));
    auto spec = JuggleSpec::Create(config);
    EXPECT_TRUE(spec.ok()) << spec.status();
    if (!spec.ok()) return nullptr;
    return *spec;
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

// The base controller of configs/right_foot_base.textproto (inverse-dynamics feed-forward,
// stance balance): the kicking leg reaches its reference at the nominal contact, and the
// zero-action character stands through a full 20 s episode with the ball out of play.
TEST(JuggleEnvBaseControllerTest, TracksTheSwingAndStaysUprightWithZeroAction) {
  std::shared_ptr<const JuggleSpec> spec = testing::LoadSpec("right_foot_base");
  ASSERT_NE(spec, nullptr);
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(11));
  env.ResetAt(*spec->graph().FindNode("right_foot_down"), walk);
  mjData* d = env.data();
  const int knee = spec->joint(kRightKnee).qpos_adr;
  double worst_knee_error = 0;
  for (int i = 0; i < spec->env().max_episode_steps(); ++i) {
    double* ball = d->qpos + spec->ball_qpos();
    ball[0] = d->qpos[0] + 0.6;
    ball[1] = d->qpos[1] - 0.1;
    ball[2] = 40.0;
    mju_zero(d->qvel + spec->ball_dof(), 6);
    const StepResult r = env.Step(kZeroAction, walk);
    if (r.outcome == Outcome::kTimeLimit) break;
    ASSERT_EQ(r.outcome, Outcome::kRunning) << "step " << i << ": " << OutcomeName(spec->outcome_names(), r.outcome);
    if (i < 50) {
      worst_knee_error =
          std::max(worst_knee_error, std::abs(d->qpos[knee] - env.reference_pose()[knee]));
    }
  }
  EXPECT_GT(d->qpos[2], 0.8);
  // Without the feed-forward the knee lags its reference by up to ~0.2 rad (0.1 with it).
  EXPECT_LT(worst_knee_error, 0.12);
}

TEST_F(JuggleEnvTest, BallOnHeadIsADisallowedContactInAFootNodeNamedByItsBody) {
  env_->ResetAt(down_, *walk_);
  EXPECT_EQ(env_->EndingDetail(), "");
  const double* head = BodyPos("neck");
  PlaceBall(head[0], head[1], head[2] + 0.175 + 0.1025 + 0.11 + 0.005);
  Outcome outcome = Outcome::kRunning;
  for (int i = 0; i < 20 && outcome == Outcome::kRunning; ++i) {
    outcome = env_->Step(kZeroAction, *walk_).outcome;
  }
  EXPECT_EQ(outcome, kBadContact);
  EXPECT_EQ(env_->EndingDetail(), "neck");  // the head is a geom of the neck body
  env_->ResetAt(down_, *walk_);
  EXPECT_EQ(env_->EndingDetail(), "");  // a new episode forgets it
}

TEST_F(JuggleEnvTest, BallOnFloorIsADisallowedContactNamedByTheFloorsGeom) {
  env_->ResetAt(down_, *walk_);
  PlaceBall(env_->data()->qpos[0] + 0.6, -0.1, 0.109);  // 1 mm into the floor
  EXPECT_EQ(env_->Step(kZeroAction, *walk_).outcome, kBadContact);
  EXPECT_EQ(env_->EndingDetail(), "floor");
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

TEST_F(JuggleEnvTest, BallErrorObservationIsTheBallMinusItsReferenceAfterTheOneHots) {
  LoadedConfig config = spec_->config();
  config.run.mutable_soccer_juggle()->mutable_env()->set_ball_error_observation(true);
  auto spec = JuggleSpec::Create(config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  const int n = (*spec)->graph().num_nodes();
  ASSERT_EQ((*spec)->obs_dim(), spec_->obs_dim() + 6);
  JuggleEnv env(*spec, Rng(3));
  env.ResetAt(down_, *walk_);
  // Ball moved off its apex reference by a known offset and velocity.
  mjData* d = env.data();
  const int b = (*spec)->ball_qpos(), v = (*spec)->ball_dof();
  d->qpos[b + 0] += 0.04;
  d->qpos[b + 1] -= 0.02;
  d->qpos[b + 2] += 0.01;
  d->qvel[v + 0] = 0.5;
  d->qvel[v + 2] = -1.0;
  mj_forward((*spec)->model(), d);
  std::vector<float> obs((*spec)->obs_dim());
  env.WriteObservation(obs.data());
  const float* err = obs.data() + kObsBase + 3 * n;
  EXPECT_NEAR(err[0], 0.04, 1e-6);
  EXPECT_NEAR(err[1], -0.02, 1e-6);
  EXPECT_NEAR(err[2], 0.01, 1e-6);
  // At the apex (φ = 0) the reference is at rest.
  EXPECT_NEAR(err[3], 0.05, 1e-6);
  EXPECT_NEAR(err[4], 0.0, 1e-6);
  EXPECT_NEAR(err[5], -0.1, 1e-6);
  // The first 88 + one-hot floats are the release's observation, unchanged.
  std::vector<float> plain(spec_->obs_dim());
  JuggleEnv same(spec_, Rng(3));
  same.ResetAt(down_, *walk_);
  same.WriteObservation(plain.data());
  for (int i = 0; i < spec_->obs_dim(); ++i) {
    if (i >= kObsBase - 12 && i < kObsBase - 3) continue;  // ball position, velocity, spin
    EXPECT_EQ(obs[i], plain[i]) << i;
  }
}

TEST_F(JuggleEnvTest, PreviousActionObservationIsTheLastAppliedActionClampedAndZeroAfterAReset) {
  for (const bool ball_error : {false, true}) {
    LoadedConfig config = spec_->config();
    config.run.mutable_soccer_juggle()->mutable_env()->set_ball_error_observation(ball_error);
    config.run.mutable_soccer_juggle()->mutable_env()->set_previous_action_observation(true);
    auto spec = JuggleSpec::Create(config);
    ASSERT_TRUE(spec.ok()) << spec.status();
    const int tail = spec_->obs_dim() + (ball_error ? 6 : 0);
    ASSERT_EQ((*spec)->obs_dim(), tail + kNumActions);
    JuggleEnv env(*spec, Rng(3));
    env.ResetAt(down_, *walk_);
    std::vector<float> obs((*spec)->obs_dim());
    env.WriteObservation(obs.data());
    for (int a = 0; a < kNumActions; ++a) EXPECT_EQ(obs[tail + a], 0.0f) << a;
    float action[kNumActions];
    for (int a = 0; a < kNumActions; ++a) action[a] = 0.01f * a;
    action[3] = 2.5f;  // applied as 1
    action[4] = -7.0f;
    env.Step(action, *walk_);
    env.WriteObservation(obs.data());
    for (int a = 0; a < kNumActions; ++a) {
      EXPECT_EQ(obs[tail + a], a == 3 ? 1.0f : a == 4 ? -1.0f : 0.01f * a) << a;
    }
    // A snapshot carries it; a reset clears it.
    std::unique_ptr<EnvSnapshot> snapshot = env.Snapshot();
    JuggleEnv copy(*spec, Rng(9));
    ASSERT_TRUE(copy.Restore(*snapshot).ok());
    std::vector<float> copied((*spec)->obs_dim());
    copy.WriteObservation(copied.data());
    EXPECT_EQ(copied, obs);
    env.ResetAt(down_, *walk_);
    env.WriteObservation(obs.data());
    for (int a = 0; a < kNumActions; ++a) EXPECT_EQ(obs[tail + a], 0.0f) << a;
  }
}

TEST_F(JuggleEnvTest, RaisedCosineSwingIsSineSquaredAndComesToRestWhereTheCycleWraps) {
  const std::shared_ptr<const JuggleSpec> raised = SpecWithSwingProfile(config::RAISED_COSINE);
  ASSERT_NE(raised, nullptr);
  const config::LegSwing& swing = spec_->graph().node(down_).spec.pose().leg_swing();
  ASSERT_EQ(swing.phase_lead(), 0);  // the paper's swing: s(φ) itself
  const int knee = spec_->joint(kRightKnee).qpos_adr;
  auto knee_at = [&](const JuggleSpec& spec, double phase) {
    CharacterPose pose;
    ComputeReferencePose(spec, down_, phase, &pose);
    return pose[knee];
  };
  for (double phase : {0.1, 0.25, 0.4, 0.5}) {
    const double s = std::sin(M_PI * phase);
    EXPECT_NEAR(knee_at(*raised, phase), -swing.knee_amplitude() * s * s, 1e-12) << phase;
    EXPECT_NEAR(knee_at(*spec_, phase), -swing.knee_amplitude() * s, 1e-12) << phase;
  }
  // Speed of the knee just after the wrap: the sine starts at amplitude·π per cycle, the raised
  // cosine from rest.
  constexpr double kDelta = 1e-4;
  const double sine_speed = std::abs(knee_at(*spec_, kDelta) - knee_at(*spec_, 0)) / kDelta;
  const double raised_speed = std::abs(knee_at(*raised, kDelta) - knee_at(*raised, 0)) / kDelta;
  EXPECT_NEAR(sine_speed, swing.knee_amplitude() * M_PI, 1e-3);
  EXPECT_LT(raised_speed, 0.005);
}

TEST_F(JuggleEnvTest, ASwingWithARestPoseMovesBetweenItAndTheAmplitudes) {
  const std::shared_ptr<const JuggleSpec> raised = SpecWithSwing([](config::LegSwing* swing) {
    swing->set_hip_rest(1.0);
    swing->set_knee_rest(1.2);
  });
  ASSERT_NE(raised, nullptr);
  const config::LegSwing& swing = spec_->graph().node(down_).spec.pose().leg_swing();
  ASSERT_EQ(swing.phase_lead(), 0);
  ASSERT_EQ(swing.hip_abduction(), 0);  // the hip is a pure pitch: its angle reads back
  const ActuatedJoint& hip = spec_->joint(kRightHip);
  const int knee = spec_->joint(kRightKnee).qpos_adr;
  for (double phase : {0.0, 0.1, 0.25, 0.5}) {
    CharacterPose pose;
    ComputeReferencePose(*raised, down_, phase, &pose);
    const double s = std::sin(M_PI * phase);  // the release's SINE profile
    const double* q = pose.data() + hip.qpos_adr;
    const double flexion = 2 * std::atan2(q[3], q[0]);  // (w, x, y, z) about z
    EXPECT_NEAR(flexion, 1.0 + (swing.hip_amplitude() - 1.0) * s, 1e-12) << phase;
    EXPECT_NEAR(pose[knee], -(1.2 + (swing.knee_amplitude() - 1.2) * s), 1e-12) << phase;
  }
}

TEST_F(JuggleEnvTest, FlatTopSwingIsOneMinusCosineToTheFourthAndFlatAtItsPeak) {
  const std::shared_ptr<const JuggleSpec> flat = SpecWithSwingProfile(config::FLAT_TOP);
  ASSERT_NE(flat, nullptr);
  const config::LegSwing& swing = spec_->graph().node(down_).spec.pose().leg_swing();
  ASSERT_EQ(swing.phase_lead(), 0);
  const int knee = spec_->joint(kRightKnee).qpos_adr;
  auto knee_at = [&](double phase) {
    CharacterPose pose;
    ComputeReferencePose(*flat, down_, phase, &pose);
    return pose[knee];
  };
  for (double phase : {0.1, 0.25, 0.4, 0.5}) {
    const double c = std::cos(M_PI * phase);
    EXPECT_NEAR(knee_at(phase), -swing.knee_amplitude() * (1 - c * c * c * c), 1e-12) << phase;
  }
  // Curvature at the peak (second difference over ±0.02 of a cycle): the raised cosine's is
  // 2π² of the amplitude; the flat top's is of order (π·0.02)², two orders smaller.
  constexpr double kH = 0.02;
  const double curvature =
      std::abs(knee_at(0.5 + kH) - 2 * knee_at(0.5) + knee_at(0.5 - kH)) / (kH * kH);
  EXPECT_LT(curvature, 0.05 * 2 * M_PI * M_PI * swing.knee_amplitude());
  // At rest where the cycle wraps.
  EXPECT_LT(std::abs(knee_at(1e-4) - knee_at(0)) / 1e-4, 0.005);
}

// Steps `spec`'s env from right_foot_down with the ball 2 cm ahead of and 1 cm left of its apex
// and expects the reference swing moved by `gains` times the predicted ball offset.
void ExpectSwingMovedByFeedback(const std::shared_ptr<const JuggleSpec>& spec_ptr,
                                const config::KickFeedback& gains) {
  const JuggleSpec& spec = *spec_ptr;
  const int down = *spec.graph().FindNode("right_foot_down");
  AdaptiveWalk walk(&spec.graph());
  JuggleEnv env(spec_ptr, Rng(3));
  env.ResetAt(down, walk);
  // A ball at rest 2 cm ahead of and 1 cm left of its apex falls straight down: the predicted
  // offset at the contact height is (0.02, 0.01).
  mjData* d = env.data();
  d->qpos[spec.ball_qpos() + 0] += 0.02;
  d->qpos[spec.ball_qpos() + 1] += 0.01;
  mj_forward(spec.model(), d);
  // Into the swing (at φ = 0 the swing is at rest and every amplitude change is 0).
  for (int i = 0; i < 10; ++i) ASSERT_EQ(env.Step(kZeroAction, walk).outcome, Outcome::kRunning);
  // The ball falls straight down, so the predicted offset is where it is now (relative to the
  // root, which has swayed since the start).
  const config::NodeSpec& node = spec.graph().node(down).spec;
  const double* ball = d->qpos + spec.ball_qpos();
  const double ex = ball[0] - d->qpos[0] - node.ball_target().x();
  const double ey = ball[1] - d->qpos[1] - node.ball_target().y();
  const double phase0 = env.cursor().phase;
  env.Step(kZeroAction, walk);
  SwingAdjust expected;
  expected.hip = gains.hip_per_m() * ex;
  expected.knee = gains.knee_per_m() * ex;
  expected.abduction = gains.abduction_per_m() * ey * -1;  // right leg: toward −y is outward
  CharacterPose pose;
  ComputeReferencePose(spec, down, phase0, &pose, expected);
  for (int i = 0; i < kCharacterNq; ++i) EXPECT_NEAR(env.reference_pose()[i], pose[i], 1e-9) << i;
  // The same swing without feedback differs (the adjustment is not zero).
  CharacterPose plain;
  ComputeReferencePose(spec, down, phase0, &plain);
  double diff = 0;
  for (int i = 0; i < kCharacterNq; ++i) diff += std::abs(plain[i] - pose[i]);
  EXPECT_GT(diff, 1e-4);
}

config::KickFeedback Gains(double hip, double knee, double abduction) {
  config::KickFeedback f;
  f.set_hip_per_m(hip);
  f.set_knee_per_m(knee);
  f.set_abduction_per_m(abduction);
  return f;
}

// `config` with node `name`'s own kick feedback set to `gains`, its graph rebuilt.
void SetNodeKickFeedback(LoadedConfig* config, const std::string& name,
                         const config::KickFeedback& gains) {
  config::ControlGraph* graph = config->run.mutable_soccer_juggle()->mutable_graph();
  bool found = false;
  for (config::NodeSpec& node : *graph->mutable_node()) {
    if (node.name() != name) continue;
    *node.mutable_kick_feedback() = gains;
    found = true;
  }
  ASSERT_TRUE(found) << name;
  absl::StatusOr<ControlGraph> built = ControlGraph::Build(*graph, config->graph_locator);
  ASSERT_TRUE(built.ok()) << built.status();
  config->graph = std::make_shared<const ControlGraph>(*std::move(built));
}

TEST_F(JuggleEnvTest, KickFeedbackMovesTheSwingByTheGainsTimesThePredictedBallOffset) {
  LoadedConfig config = spec_->config();
  *config.run.mutable_soccer_juggle()->mutable_env()->mutable_kick_feedback() = Gains(3, -2, 1.5);
  auto spec = JuggleSpec::Create(config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  ExpectSwingMovedByFeedback(*spec, Gains(3, -2, 1.5));
}

TEST_F(JuggleEnvTest, ANodesOwnKickFeedbackReplacesTheEnvsAndActsWithoutIt) {
  for (const bool env_feedback : {true, false}) {
    SCOPED_TRACE(env_feedback ? "env feedback set" : "no env feedback");
    LoadedConfig config = spec_->config();
    if (env_feedback) {
      *config.run.mutable_soccer_juggle()->mutable_env()->mutable_kick_feedback() =
          Gains(3, -2, 1.5);
    }
    SetNodeKickFeedback(&config, "right_foot_down", Gains(-1, 0.5, 6));
    auto spec = JuggleSpec::Create(config);
    ASSERT_TRUE(spec.ok()) << spec.status();
    ExpectSwingMovedByFeedback(*spec, Gains(-1, 0.5, 6));
  }
}

TEST_F(JuggleEnvTest, ANodesZeroKickFeedbackTurnsTheEnvsOffThere) {
  LoadedConfig config = spec_->config();
  *config.run.mutable_soccer_juggle()->mutable_env()->mutable_kick_feedback() = Gains(3, -2, 1.5);
  SetNodeKickFeedback(&config, "right_foot_down", Gains(0, 0, 0));  // present, every gain 0
  auto spec = JuggleSpec::Create(config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  const int down = *(*spec)->graph().FindNode("right_foot_down");
  AdaptiveWalk walk(&(*spec)->graph());
  JuggleEnv env(*spec, Rng(3));
  env.ResetAt(down, walk);
  mjData* d = env.data();
  d->qpos[(*spec)->ball_qpos() + 0] += 0.02;
  mj_forward((*spec)->model(), d);
  for (int i = 0; i < 10; ++i) ASSERT_EQ(env.Step(kZeroAction, walk).outcome, Outcome::kRunning);
  const double phase0 = env.cursor().phase;
  env.Step(kZeroAction, walk);
  CharacterPose plain;
  ComputeReferencePose(**spec, down, phase0, &plain);
  for (int i = 0; i < kCharacterNq; ++i) EXPECT_NEAR(env.reference_pose()[i], plain[i], 1e-12) << i;
}

// The start variation of the recipe's config: within its ranges, different per seed, the same
// for the same seed.
class StartVariationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = testing::LoadSpec("right_foot");
    exact_ = testing::LoadSpec("right_foot_paper");
    ASSERT_NE(spec_, nullptr);
    ASSERT_NE(exact_, nullptr);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    down_ = *spec_->graph().FindNode("right_foot_down");
  }
  std::vector<double> StartState(const std::shared_ptr<const JuggleSpec>& spec, uint64_t seed) {
    JuggleEnv env(spec, Rng::ForStream(seed, 0, 3));
    env.ResetAt(down_, *walk_);
    const mjData* d = env.data();
    std::vector<double> state(d->qpos, d->qpos + spec->model()->nq);
    state.insert(state.end(), d->qvel, d->qvel + spec->model()->nv);
    return state;
  }
  std::shared_ptr<const JuggleSpec> spec_, exact_;
  std::unique_ptr<AdaptiveWalk> walk_;
  int down_ = -1;
};

TEST_F(StartVariationTest, SameSeedSameStartAndOtherSeedsOtherStarts) {
  EXPECT_EQ(StartState(spec_, 5), StartState(spec_, 5));
  EXPECT_NE(StartState(spec_, 5), StartState(spec_, 6));
  EXPECT_EQ(StartState(exact_, 5), StartState(exact_, 6)) << "no variation: one start";
}

TEST_F(StartVariationTest, EveryPerturbationStaysInsideItsConfiguredRange) {
  const config::StartVariation& v = spec_->env().start();
  ASSERT_GT(v.ball_position(), 0);
  ASSERT_GT(v.joint_speed(), 0);
  const int nq = spec_->model()->nq;
  const std::vector<double> nominal = StartState(exact_, 1);
  double max_ball_pos = 0, max_ball_vel = 0, max_hinge = 0, max_speed = 0, max_rotation = 0;
  for (uint64_t seed = 0; seed < 200; ++seed) {
    const std::vector<double> s = StartState(spec_, seed);
    for (int c = 0; c < 3; ++c) {
      max_ball_pos = std::max(max_ball_pos, std::abs(s[spec_->ball_qpos() + c] - nominal[spec_->ball_qpos() + c]));
      max_ball_vel = std::max(max_ball_vel, std::abs(s[nq + spec_->ball_dof() + c]));
    }
    for (int j = 0; j < kNumJoints; ++j) {
      const ActuatedJoint& joint = spec_->joint(j);
      for (int d = 0; d < joint.dofs; ++d) {
        max_speed = std::max(max_speed, std::abs(s[nq + joint.dof_adr + d]));
      }
      if (joint.dofs == 1) {
        max_hinge = std::max(max_hinge, std::abs(s[joint.qpos_adr] - nominal[joint.qpos_adr]));
      } else {
        double rotation[3];
        mju_subQuat(rotation, s.data() + joint.qpos_adr, nominal.data() + joint.qpos_adr);
        for (double r : rotation) max_rotation = std::max(max_rotation, std::abs(r));
      }
    }
  }
  EXPECT_LE(max_ball_pos, v.ball_position());
  EXPECT_GT(max_ball_pos, 0.8 * v.ball_position()) << "200 draws reach near the range's edge";
  EXPECT_LE(max_ball_vel, v.ball_velocity());
  EXPECT_GT(max_ball_vel, 0.8 * v.ball_velocity());
  EXPECT_LE(max_hinge, v.joint_angle());
  EXPECT_LE(max_speed, v.joint_speed());
  EXPECT_GT(max_speed, 0.8 * v.joint_speed());
  // A rotation of ± a about each axis in turn stays within ~√3·a of the nominal.
  EXPECT_LE(max_rotation, std::sqrt(3.0) * v.joint_angle() + 1e-9);
  EXPECT_GT(max_rotation, 0.5 * v.joint_angle());
}

TEST_F(StartVariationTest, RandomPhaseStartsPlaceTheBallOnItsFallAtThatPhase) {
  LoadedConfig config = exact_->config();
  config::StartVariation* start =
      config.run.mutable_soccer_juggle()->mutable_env()->mutable_start();
  start->set_random_phase_fraction(1.0);
  start->set_max_phase(0.3);
  auto spec = JuggleSpec::Create(config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  const double g = (*spec)->env().gravity();
  const double apex = (*spec)->graph().node(down_).spec.apex_height();
  for (uint64_t seed = 0; seed < 20; ++seed) {
    JuggleEnv env(*spec, Rng::ForStream(seed, 0, 0));
    env.ResetAt(down_, *walk_);
    const double phase = env.cursor().phase;
    EXPECT_GE(phase, 0);
    EXPECT_LE(phase, 0.3);
    // Ballistic: v = −g·t and z = apex − ½·g·t² at t = φ / phase_speed control steps.
    const double t = phase / env.cursor().phase_speed * (*spec)->control_dt();
    const double* ball = env.data()->qpos + (*spec)->ball_qpos();
    EXPECT_NEAR(ball[2], apex - 0.5 * g * t * t, 1e-9);
    EXPECT_NEAR(env.data()->qvel[(*spec)->ball_dof() + 2], -g * t, 1e-9);
  }
}

}  // namespace
}  // namespace juggle::soccer_juggle
