// The label-spread measurement's student mix: β = 1 executes the student's own actions (checked
// against a plain rollout of the same start), β = 0 the planner's; DART noise is added to the
// executed action and held for its steps (checked state by state against a plain rollout);
// bad options are refused.
#include "planner/label_spread.h"
#include "planner/soccer_juggle/plan.h"

#include <algorithm>
#include <cmath>

#include "common/adaptive_walk.h"
#include "common/testing/constant_policy.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::planner {
namespace {

using juggle::testing::ConstantPolicy;

class LabelSpreadTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(::juggle::testing::RepoPath("configs/right_foot_planner.textproto"));
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *std::move(config);
    config::PlannerConfig& p = *config_.run.mutable_planner();
    p.set_samples(6);
    p.set_iterations(1);
    p.set_horizon_steps(20);
    p.set_threads(1);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
  }

  // Steps of a plain rollout of episode `e`'s start with one constant action.
  int PlainRolloutSteps(uint64_t seed, int e, float action, int max_steps, int* juggles) {
    const AdaptiveWalk walk(&spec_->graph());
    std::unique_ptr<Env> env = spec_->NewEnv(Rng::ForStream(seed, 0, e));
    env->Reset(walk);
    std::vector<float> a(spec_->act_dim(), action);
    int steps = 0;
    while (steps < max_steps) {
      ++steps;
      if (env->Step(a.data(), walk).outcome != Outcome::kRunning) break;
    }
    *juggles = env->juggles();
    return steps;
  }

  LoadedConfig config_;
  std::shared_ptr<const EnvSpec> spec_;
};

TEST_F(LabelSpreadTest, AFullMixExecutesTheStudentsOwnActions) {
  const float bias = 0.9f;  // every joint pushed hard: the character falls within the episode
  const EigenPolicy student = ConstantPolicy(spec_->obs_dim(), spec_->act_dim(), bias);
  LabelSpreadOptions o;
  o.episodes = 1;
  o.seconds = 1.5;
  o.forks = 0;
  o.seed = 7;
  o.student = &student;
  o.student_mix = 1.0;
  absl::StatusOr<LabelSpreadReport> r = MeasureLabelSpread(spec_, config_, o, nullptr);
  ASSERT_TRUE(r.ok()) << r.status();
  int juggles = 0;
  const int max_steps = static_cast<int>(std::lround(o.seconds / spec_->control_dt()));
  // The student's constant action, exactly (label + 1·(student − label) in double is exact).
  const std::vector<float> zeros(spec_->obs_dim(), 0.0f);
  const float action = student.MeanActions(zeros.data(), 1)(0, 0);
  EXPECT_NEAR(action, std::tanh(bias), 1e-5);
  const int plain_steps = PlainRolloutSteps(o.seed, 0, action, max_steps, &juggles);
  ASSERT_LT(plain_steps, max_steps);  // it ends early, unlike the planner's own episode
  EXPECT_EQ(r->steps, plain_steps);
  EXPECT_EQ(r->juggles, juggles);
  EXPECT_EQ(r->states, 0);  // no forks: no spread measured
  // The labels are the planner's, not the student's: its error against them is not zero.
  ASSERT_EQ(r->student_rmse.size(), static_cast<size_t>(spec_->act_dim()));
  double largest = 0;
  for (double e : r->student_rmse) largest = std::max(largest, e);
  EXPECT_GT(largest, 0.05);
}

TEST_F(LabelSpreadTest, NoMixLetsThePlannerDriveWhateverTheStudent) {
  const EigenPolicy far = ConstantPolicy(spec_->obs_dim(), spec_->act_dim(), 0.9f);
  const EigenPolicy near = ConstantPolicy(spec_->obs_dim(), spec_->act_dim(), -0.9f);
  LabelSpreadOptions o;
  o.episodes = 1;
  o.seconds = 0.4;
  o.forks = 0;
  o.student = &far;
  absl::StatusOr<LabelSpreadReport> a = MeasureLabelSpread(spec_, config_, o, nullptr);
  o.student = &near;
  absl::StatusOr<LabelSpreadReport> b = MeasureLabelSpread(spec_, config_, o, nullptr);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->label_std, b->label_std);  // the same visited states and labels
  EXPECT_NE(a->student_rmse, b->student_rmse);
}

TEST_F(LabelSpreadTest, KeptRowsHoldEveryVisitedStateWithItsLabelAndKick) {
  LabelSpreadOptions o;
  o.episodes = 2;
  o.seconds = 0.3;
  o.forks = 0;
  o.keep_rows = true;
  absl::StatusOr<LabelSpreadReport> r = MeasureLabelSpread(spec_, config_, o, nullptr);
  ASSERT_TRUE(r.ok()) << r.status();
  const int act = spec_->act_dim();
  ASSERT_EQ(r->episode_steps.size(), 2u);
  EXPECT_EQ(r->episode_steps[0] + r->episode_steps[1], r->steps);
  EXPECT_EQ(r->row_obs.size(), size_t(r->steps) * spec_->obs_dim());
  ASSERT_EQ(r->row_labels.size(), size_t(r->steps) * act);
  EXPECT_EQ(r->row_kicks.size(), size_t(r->steps) * kKickVariables);
  // The kept labels are the ones the report's spread was computed from.
  for (int i = 0; i < act; ++i) {
    double sum = 0, sq = 0;
    for (int k = 0; k < r->steps; ++k) {
      const double x = r->row_labels[size_t(k) * act + i];
      sum += x;
      sq += x * x;
    }
    const double m = sum / r->steps;
    EXPECT_NEAR(std::sqrt(std::max(0.0, sq / r->steps - m * m)), r->label_std[i], 1e-6) << i;
  }
  // The planner moved some kick variable away from the nominal swing.
  double largest = 0;
  for (float v : r->row_kicks) largest = std::max(largest, double(std::abs(v)));
  EXPECT_GT(largest, 0.0);
}

TEST_F(LabelSpreadTest, ExpertNoiseIsAddedToTheExecutedActionAndHeldForItsSteps) {
  const EigenPolicy student = ConstantPolicy(spec_->obs_dim(), spec_->act_dim(), 0.1f);
  LabelSpreadOptions o;
  o.episodes = 1;
  o.seconds = 0.3;
  o.forks = 0;
  o.seed = 3;
  o.student = &student;
  o.student_mix = 1.0;  // the student's constant action, so the executed action is known
  o.expert_noise = 0.3;
  o.noise_hold_steps = 4;
  o.keep_rows = true;
  absl::StatusOr<LabelSpreadReport> r = MeasureLabelSpread(spec_, config_, o, nullptr);
  ASSERT_TRUE(r.ok()) << r.status();
  // The same episode stepped directly: the constant action plus the noise of the salted
  // streams, drawn every 4th step, clamped.
  const std::vector<float> zeros(spec_->obs_dim(), 0.0f);
  const float action = student.MeanActions(zeros.data(), 1)(0, 0);
  const AdaptiveWalk walk(&spec_->graph());
  std::unique_ptr<Env> env = spec_->NewEnv(Rng::ForStream(o.seed, 0, 0));
  env->Reset(walk);
  Rng noise = Rng::ForStream(o.seed ^ 0x6e6f697365ULL, 0, 0);  // label_spread.cc's kNoiseSalt
  const int act = spec_->act_dim(), dim = spec_->obs_dim();
  std::vector<double> draw(act);
  std::vector<float> obs(dim);
  int steps = 0;
  for (; steps < r->steps; ++steps) {
    env->WriteObservation(obs.data());
    ASSERT_TRUE(std::equal(obs.begin(), obs.end(), r->row_obs.begin() + size_t(steps) * dim))
        << "state " << steps;
    if (steps % 4 == 0) {
      for (double& x : draw) x = o.expert_noise * noise.Normal();
    }
    std::vector<float> executed(act);
    for (int i = 0; i < act; ++i) executed[i] = std::clamp(float(action + draw[i]), -1.0f, 1.0f);
    if (env->Step(executed.data(), walk).outcome != Outcome::kRunning) break;
  }
  EXPECT_GE(steps, r->steps - 1);
  // Without the noise the episode visits other states.
  o.expert_noise = 0;
  absl::StatusOr<LabelSpreadReport> clean = MeasureLabelSpread(spec_, config_, o, nullptr);
  ASSERT_TRUE(clean.ok()) << clean.status();
  EXPECT_NE(clean->row_obs, r->row_obs);
  // The labels are the planner's clean actions: at the first state, before any noise acted,
  // the noisy run's label equals the noiseless run's.
  ASSERT_GE(clean->row_labels.size(), size_t(act));
  EXPECT_TRUE(std::equal(r->row_labels.begin(), r->row_labels.begin() + act,
                         clean->row_labels.begin()));
}

TEST_F(LabelSpreadTest, RefusesBadMixesForksAndNoise) {
  LabelSpreadOptions o;
  o.episodes = 1;
  o.seconds = 0.1;  // a check that went missing would cost little before the test failed
  o.forks = 0;
  o.student_mix = 0.5;
  EXPECT_EQ(MeasureLabelSpread(spec_, config_, o, nullptr).status().code(),
            absl::StatusCode::kInvalidArgument);
  const EigenPolicy student = ConstantPolicy(spec_->obs_dim(), spec_->act_dim(), 0.0f);
  o.student = &student;
  o.student_mix = 1.5;
  EXPECT_EQ(MeasureLabelSpread(spec_, config_, o, nullptr).status().code(),
            absl::StatusCode::kInvalidArgument);
  o.student_mix = 0;
  o.forks = 1;
  EXPECT_EQ(MeasureLabelSpread(spec_, config_, o, nullptr).status().code(),
            absl::StatusCode::kInvalidArgument);
  o.forks = 0;
  o.expert_noise = -0.1;
  EXPECT_EQ(MeasureLabelSpread(spec_, config_, o, nullptr).status().code(),
            absl::StatusCode::kInvalidArgument);
  o.expert_noise = 0.1;
  o.noise_hold_steps = 0;
  EXPECT_EQ(MeasureLabelSpread(spec_, config_, o, nullptr).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace juggle::planner
