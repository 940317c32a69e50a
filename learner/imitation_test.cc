// Planner-guided training's learner side on a small fixed problem: cloning drives the
// student's action error down (checked through the workers' Eigen inference, an independent
// path), pretraining leaves the actor to the demonstrations, the imitation term pulls PPO
// toward the labels, and the schedule.
#include <cmath>
#include <vector>

#include "common/eigen_policy.h"
#include "common/rng.h"
#include "gtest/gtest.h"
#include "learner/demo_buffer.h"
#include "learner/imitation_schedule.h"
#include "learner/ppo_trainer.h"
#include "learner/testing/point_mass.h"

namespace juggle {
namespace {

using testing::Collect;
using testing::PointMass;
using testing::SmallModel;
using testing::SmallPpo;

// The teacher of the fixed problem: steer against the position, saturating.
void Teacher(const float* obs, float* action) {
  for (int a = 0; a < 2; ++a) action[a] = std::tanh(-1.5f * obs[a]);
}

// `unrolls` × 20 labelled states drawn uniformly from [-1, 1]², as one batch.
UnrollBatch TeacherBatch(int unrolls, uint64_t seed) {
  Rng rng(seed);
  UnrollBatch b;
  b.num_unrolls = unrolls;
  b.unroll_length = 20;
  b.obs_dim = b.act_dim = 2;
  const int n = unrolls * 20;
  b.obs.resize(n * 2);
  b.labels.resize(n * 2);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 2; ++d) b.obs[i * 2 + d] = float(rng.Uniform(-1, 1));
    Teacher(&b.obs[i * 2], &b.labels[i * 2]);
  }
  b.labelled.assign(unrolls, 1);
  return b;
}

// Mean squared error of the exported policy's mean action (Eigen) against the teacher on
// fresh states.
double StudentError(const PpoTrainer& trainer) {
  const EigenPolicy policy = *EigenPolicy::Create(SmallModel(), trainer.ExportPolicy(), 2, 2);
  const UnrollBatch probe = TeacherBatch(10, 999);
  const RowMatrix mean = policy.MeanActions(probe.obs.data(), probe.num_samples());
  double sum = 0;
  for (int64_t i = 0; i < probe.num_samples(); ++i) {
    for (int a = 0; a < 2; ++a) sum += std::pow(mean(i, a) - probe.labels[i * 2 + a], 2);
  }
  return sum / (probe.num_samples() * 2);
}

ImitationTerm CloneOnly(const DemoBuffer* demos) {
  ImitationTerm t;
  t.demos = demos;
  t.clone_only = true;
  t.clone_steps = 50;
  t.clone_minibatch = 128;
  t.clone_lr = 3e-3;
  return t;
}

TEST(ImitationTest, CloningOnAFixedLabelledSetDrivesTheStudentsActionErrorDown) {
  DemoBuffer demos(10000, 2, 2);
  demos.AddLabelled(TeacherBatch(100, 1));
  PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, 5);
  std::vector<PointMass> envs;
  for (int i = 0; i < 8; ++i) envs.emplace_back(100 + i);
  Rng rng(7);
  UnrollBatch batch;
  const double before = StudentError(trainer);
  for (int it = 0; it < 8; ++it) {
    Collect(trainer, &envs, &rng, &batch);
    absl::StatusOr<UpdateStats> stats = trainer.Update(batch, 0, CloneOnly(&demos));
    ASSERT_TRUE(stats.ok()) << stats.status();
    EXPECT_TRUE(stats->cloned_only);
    EXPECT_GT(stats->imitation_loss, 0);
  }
  const double after = StudentError(trainer);
  EXPECT_GT(before, 0.2);  // the untrained student is far off (labels are ~±0.9)
  EXPECT_LT(after, 0.01) << "before " << before;
  EXPECT_LT(after, before / 20);
  // The torch-side error on the buffer agrees with the Eigen-side one on fresh states.
  EXPECT_NEAR(trainer.ImitationError(demos), after, 0.01);
}

TEST(ImitationTest, PretrainingWithoutDemonstrationsLeavesTheActorAlone) {
  PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, 5);
  std::vector<PointMass> envs;
  for (int i = 0; i < 8; ++i) envs.emplace_back(100 + i);
  Rng rng(7);
  UnrollBatch batch;
  Collect(trainer, &envs, &rng, &batch);
  const std::vector<float> actor = trainer.ExportPolicy().values();
  const std::vector<float> all = trainer.ExportAll().values();
  ASSERT_TRUE(trainer.Update(batch, 0, CloneOnly(nullptr)).ok());
  EXPECT_EQ(trainer.ExportPolicy().values(), actor);  // the actor did not move
  EXPECT_NE(trainer.ExportAll().values(), all);       // the critic did
  EXPECT_EQ(trainer.version(), 1);
}

TEST(ImitationTest, ImitationTermPullsPpoTowardTheLabels) {
  DemoBuffer demos(10000, 2, 2);
  demos.AddLabelled(TeacherBatch(100, 1));
  auto error_after_ppo = [&](double weight) {
    PpoTrainer trainer(SmallModel(), SmallPpo(), 2, 2, 5);
    std::vector<PointMass> envs;
    for (int i = 0; i < 8; ++i) envs.emplace_back(100 + i);
    Rng rng(7);
    UnrollBatch batch;
    ImitationTerm term;
    term.demos = &demos;
    term.weight = weight;
    for (int it = 0; it < 5; ++it) {
      Collect(trainer, &envs, &rng, &batch);
      absl::StatusOr<UpdateStats> stats = trainer.Update(batch, 0, term);
      EXPECT_TRUE(stats.ok());
      EXPECT_EQ(stats->imitation_weight, weight);
    }
    return StudentError(trainer);
  };
  const double without = error_after_ppo(0), with = error_after_ppo(10);
  EXPECT_LT(with, without / 3) << "without " << without;
}

TEST(ImitationTest, ScheduleClonesThenDecaysTheWeightToItsFloor) {
  config::ImitationConfig im;
  im.set_pretrain_iterations(3);
  im.set_weight(2);
  im.set_decay(0.5);
  im.set_floor_fraction(0.1);
  im.set_min_buffer(5);
  DemoBuffer demos(100, 2, 2);
  demos.AddLabelled(TeacherBatch(1, 1));  // 20 states
  for (int64_t it = 0; it < 3; ++it) {
    const ImitationTerm t = ImitationFor(im, it, &demos);
    EXPECT_TRUE(t.clone_only) << it;
    EXPECT_EQ(t.weight, 0);
    EXPECT_EQ(t.demos, &demos);
  }
  // Label errors in units of each action's label spread, floored at min_label_std.
  im.set_min_label_std(0.08);
  const std::vector<double> var = demos.LabelVariance();
  const std::vector<float> w = ImitationFor(im, 3, &demos).action_weights;
  ASSERT_EQ(w.size(), 2u);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GT(var[a], 0.0064);
    EXPECT_FLOAT_EQ(w[a], float(1 / var[a]));
  }
  im.set_min_label_std(10);  // a floor above every spread: weights 1/100
  EXPECT_FLOAT_EQ(ImitationFor(im, 3, &demos).action_weights[0], 0.01f);
  im.set_min_label_std(0);
  EXPECT_TRUE(ImitationFor(im, 3, &demos).action_weights.empty());
  EXPECT_EQ(ImitationFor(im, 3, &demos).weight, 2);
  EXPECT_FALSE(ImitationFor(im, 3, &demos).clone_only);
  EXPECT_EQ(ImitationFor(im, 4, &demos).weight, 1);
  EXPECT_EQ(ImitationFor(im, 6, &demos).weight, 0.25);
  EXPECT_DOUBLE_EQ(ImitationFor(im, 7, &demos).weight, 0.2);   // 0.125 is below the floor
  EXPECT_DOUBLE_EQ(ImitationFor(im, 500, &demos).weight, 0.2);
  // Below min_buffer: still pretraining, but nothing to clone.
  DemoBuffer few(100, 2, 2);
  EXPECT_TRUE(ImitationFor(im, 0, &few).clone_only);
  EXPECT_EQ(ImitationFor(im, 0, &few).demos, nullptr);
  // No buffer (imitation off): a plain PPO term.
  EXPECT_FALSE(ImitationFor(im, 0, nullptr).clone_only);
  EXPECT_EQ(ImitationFor(im, 9, nullptr).weight, 0);
}

}  // namespace
}  // namespace juggle
