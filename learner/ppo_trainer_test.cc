// PPO end to end on a small continuous-control problem written for the test, plus the
// trainer's contracts (malformed batches change nothing, determinism).
#include "learner/ppo_trainer.h"
#include "learner/testing/point_mass.h"

#include <cmath>
#include <vector>

#include "common/eigen_policy.h"
#include "common/rng.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using testing::Collect;
using testing::PointMass;
using testing::SmallModel;
using testing::SmallPpo;

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

// The adaptive learning rate follows the KL: a tiny target drives it down to its floor, a huge
// one up to its ceiling; the release's decay would do neither in 6 iterations.
double LearningRateAfter(double desired_kl, int iterations) {
  config::PpoConfig ppo = SmallPpo();
  ppo.set_desired_kl(desired_kl);
  ppo.set_actor_lr(1e-3);
  ppo.set_min_actor_lr(1e-5);
  ppo.set_max_actor_lr(1e-2);
  ppo.set_reset_optimizer_each_iteration(false);
  PpoTrainer trainer(SmallModel(), ppo, 2, 2, 5);
  std::vector<PointMass> envs;
  for (int i = 0; i < 16; ++i) envs.emplace_back(100 + i);
  Rng rng(7);
  UnrollBatch batch;
  for (int it = 0; it < iterations; ++it) {
    Collect(trainer, &envs, &rng, &batch);
    EXPECT_TRUE(trainer.Update(batch).ok());
  }
  return trainer.actor_lr();
}

TEST(PpoTrainerTest, AdaptiveLearningRateFallsAboveTheTargetKlAndRisesBelowIt) {
  EXPECT_NEAR(LearningRateAfter(/*desired_kl=*/1e-12, 6), 1e-5, 1e-12);
  EXPECT_NEAR(LearningRateAfter(/*desired_kl=*/1e6, 6), 1e-2, 1e-12);
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
