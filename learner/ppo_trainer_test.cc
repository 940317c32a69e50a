// PPO end to end on a small continuous-control problem written for the test, plus the
// trainer's contracts (malformed batches change nothing, determinism).
#include "learner/ppo_trainer.h"

#include <cmath>
#include <vector>

#include "common/eigen_policy.h"
#include "common/rng.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

// A point mass in the plane must reach the origin: x' = x + 0.1·a, reward exp(−5·|x'|²)
// (in (0, 1]), 20 steps per episode (time-limit truncation), start uniform in [−1, 1]².
class PointMass {
 public:
  static constexpr int kObs = 2, kAct = 2, kHorizon = 20;
  explicit PointMass(uint64_t seed) : rng_(seed) { Reset(); }
  void Reset() {
    x_[0] = rng_.Uniform(-1, 1);
    x_[1] = rng_.Uniform(-1, 1);
    t_ = 0;
  }
  const float* obs() const { return x_; }
  // Returns the reward; *truncated when the episode hit its horizon (then it resets).
  float Step(const float* a, bool* truncated, float* final_obs) {
    for (int i = 0; i < 2; ++i) x_[i] += 0.1f * a[i];
    const float r = std::exp(-5.0f * (x_[0] * x_[0] + x_[1] * x_[1]));
    *truncated = ++t_ >= kHorizon;
    if (*truncated) {
      final_obs[0] = x_[0];
      final_obs[1] = x_[1];
      Reset();
    }
    return r;
  }

 private:
  Rng rng_;
  float x_[2];
  int t_ = 0;
};

config::ModelConfig SmallModel() {
  config::ModelConfig m;
  m.set_num_experts(4);
  m.add_hidden(64);
  m.add_hidden(64);
  m.add_gate_hidden(32);
  m.add_gate_hidden(32);
  m.set_log_std(-1.0);
  return m;
}

config::PpoConfig SmallPpo() {
  config::PpoConfig p;
  p.set_unroll_length(20);
  p.set_gamma(0.95);
  p.set_gae_lambda(0.95);
  p.set_epochs(5);
  p.set_num_minibatches(4);
  p.set_actor_lr(3e-3);
  p.set_min_actor_lr(3e-4);
  p.set_lr_decay(0.98);
  p.set_critic_lr_factor(3);
  p.set_normalize_advantages(true);
  p.set_torch_threads(1);
  return p;
}

// Collects one batch of `envs` unrolls with the exported policy; returns the mean reward.
double Collect(const PpoTrainer& trainer, std::vector<PointMass>* envs, Rng* rng,
               UnrollBatch* batch) {
  const config::ModelConfig model = SmallModel();
  const FlatParameters params = trainer.ExportPolicy();
  const EigenPolicy policy = *EigenPolicy::Create(model, params, 2, 2);
  const int U = static_cast<int>(envs->size()), T = 20;
  *batch = UnrollBatch();
  batch->num_unrolls = U;
  batch->unroll_length = T;
  batch->obs_dim = batch->act_dim = 2;
  batch->obs.resize(U * T * 2);
  batch->actions.resize(U * T * 2);
  batch->log_probs.resize(U * T);
  batch->rewards.resize(U * T);
  batch->done.assign(U * T, 0);
  batch->truncated.assign(U * T, 0);
  batch->bootstrap_obs.resize(U * 2);
  batch->policy_version.assign(U, trainer.version());
  double reward_sum = 0;
  for (int u = 0; u < U; ++u) {
    PointMass& env = (*envs)[u];
    for (int t = 0; t < T; ++t) {
      const int i = u * T + t;
      std::copy(env.obs(), env.obs() + 2, &batch->obs[i * 2]);
      policy.Act(env.obs(), 1, rng, &batch->actions[i * 2], &batch->log_probs[i]);
      bool truncated = false;
      float final_obs[2];
      batch->rewards[i] = env.Step(&batch->actions[i * 2], &truncated, final_obs);
      reward_sum += batch->rewards[i];
      if (truncated) {
        batch->truncated[i] = 1;
        batch->truncated_obs.insert(batch->truncated_obs.end(), final_obs, final_obs + 2);
      }
    }
    std::copy(env.obs(), env.obs() + 2, &batch->bootstrap_obs[u * 2]);
  }
  return reward_sum / (U * T);
}

TEST(PpoTrainerTest, LearnsToDriveAPointMassToTheGoal) {
  PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, /*seed=*/5);
  std::vector<PointMass> envs;
  for (int i = 0; i < 32; ++i) envs.emplace_back(100 + i);
  Rng rng(7);
  UnrollBatch batch;
  const double untrained = Collect(trainer, &envs, &rng, &batch);
  double trained = 0;
  for (int it = 0; it < 60; ++it) {
    ASSERT_TRUE(trainer.Update(batch).ok());
    trained = Collect(trainer, &envs, &rng, &batch);
  }
  // Untrained ~0.2 per step; steering to the origin within ~10 steps gives > 0.6.
  EXPECT_LT(untrained, 0.35);
  EXPECT_GT(trained, 0.6) << "untrained " << untrained;
}

TEST(PpoTrainerTest, MalformedBatchIsRejectedAndChangesNothing) {
  PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, 5);
  std::vector<PointMass> envs(4, PointMass(1));
  Rng rng(7);
  UnrollBatch batch;
  Collect(trainer, &envs, &rng, &batch);
  batch.rewards[3] = std::nanf("");
  const std::vector<float> before = trainer.ExportAll().values();
  const absl::StatusOr<UpdateStats> r = trainer.Update(batch);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(r.status().message(), ::testing::HasSubstr("rewards"));
  EXPECT_EQ(trainer.version(), 0);
  EXPECT_EQ(trainer.ExportAll().values(), before);
}

TEST(PpoTrainerTest, StaleBatchIsAFailedPrecondition) {
  PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, 5);
  std::vector<PointMass> envs(4, PointMass(1));
  Rng rng(7);
  UnrollBatch batch;
  Collect(trainer, &envs, &rng, &batch);
  ASSERT_TRUE(trainer.Update(batch).ok());  // version 0 -> 1
  EXPECT_EQ(trainer.Update(batch).status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(trainer.Update(batch, /*max_policy_lag=*/1).ok());
}

TEST(PpoTrainerTest, SameSeedGivesIdenticalParameters) {
  auto run = [] {
    PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, 9);
    std::vector<PointMass> envs;
    for (int i = 0; i < 8; ++i) envs.emplace_back(i);
    Rng rng(3);
    UnrollBatch batch;
    for (int it = 0; it < 3; ++it) {
      Collect(trainer, &envs, &rng, &batch);
      EXPECT_TRUE(trainer.Update(batch).ok());
    }
    return trainer.ExportAll().values();
  };
  EXPECT_EQ(run(), run());
}

TEST(PpoTrainerTest, LearningRateDecaysToItsFloor) {
  config::PpoConfig ppo = SmallPpo();
  ppo.set_actor_lr(1e-3);
  ppo.set_lr_decay(0.5);
  ppo.set_min_actor_lr(3e-4);
  PpoTrainer trainer(SmallModel(), ppo, 2, 2, 1);
  std::vector<PointMass> envs(2, PointMass(1));
  Rng rng(1);
  UnrollBatch batch;
  const double expected[] = {5e-4, 3e-4, 3e-4};
  for (double lr : expected) {
    Collect(trainer, &envs, &rng, &batch);
    ASSERT_TRUE(trainer.Update(batch).ok());
    EXPECT_NEAR(trainer.actor_lr(), lr, 1e-12);
  }
}

}  // namespace
}  // namespace juggle
