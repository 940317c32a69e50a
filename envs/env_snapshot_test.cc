// Snapshots are exact: an env restored from a snapshot steps bit for bit as the original,
// for every family; snapshots of another family, model or config are refused.
#include "envs/env_snapshot.h"

#include <memory>
#include <vector>

#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/task_env.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

std::shared_ptr<const EnvSpec> LoadFamilySpec(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig(name);
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// Random actions in ±0.2 on the first `noisy` of act_dim dimensions, zero on the rest (so
// the copies are driven by something other than zero).
std::vector<float> RandomActions(Rng* rng, int act_dim, int noisy) {
  std::vector<float> a(act_dim, 0.0f);
  for (int i = 0; i < noisy; ++i) a[i] = static_cast<float>(rng->Uniform(-0.2, 0.2));
  return a;
}

// Steps `original` and `copy` with the same actions for `steps` control steps (or until the
// original's episode ends) and expects identical results, observations and physics. Returns
// the steps compared.
int ExpectSameFuture(const EnvSpec& spec, Env* original, Env* copy, int steps, int noisy) {
  const AdaptiveWalk walk(&spec.graph());
  Rng actions(77);
  std::vector<float> obs_a(spec.obs_dim()), obs_b(spec.obs_dim());
  PhysicsSnapshot after;
  for (int t = 0; t < steps; ++t) {
    const std::vector<float> a = RandomActions(&actions, spec.act_dim(), noisy);
    const StepResult ra = original->Step(a.data(), walk);
    const StepResult rb = copy->Step(a.data(), walk);
    EXPECT_EQ(ra.reward, rb.reward) << "step " << t;
    EXPECT_EQ(ra.outcome, rb.outcome) << "step " << t;
    after.Save(spec.model(), original->data());
    EXPECT_TRUE(after.Equals(copy->data())) << "physics differ after step " << t;
    original->WriteObservation(obs_a.data());
    copy->WriteObservation(obs_b.data());
    EXPECT_EQ(obs_a, obs_b) << "step " << t;
    EXPECT_EQ(original->juggles(), copy->juggles());
    EXPECT_EQ(original->node(), copy->node());
    if (ra.outcome != Outcome::kRunning || ::testing::Test::HasFailure()) return t + 1;
  }
  return steps;
}

TEST(EnvSnapshotTest, SoccerCopyStepsBitForBitOverAJuggleCycle) {
  const std::shared_ptr<const EnvSpec> spec = LoadFamilySpec("right_foot_recipe");
  ASSERT_NE(spec, nullptr);
  const AdaptiveWalk walk(&spec->graph());
  std::unique_ptr<Env> original = spec->NewEnv(Rng(5));
  original->Reset(walk);
  // Mid-flight, so contacts, the kick feedback and the phase clock are all live.
  const std::vector<float> zero(spec->act_dim(), 0.0f);
  for (int t = 0; t < 7; ++t) original->Step(zero.data(), walk);
  std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
  ASSERT_NE(snapshot, nullptr);
  EXPECT_EQ(snapshot->family(), "soccer_juggle");
  // A fresh env of the same spec with another random stream: the restore replaces it all.
  std::unique_ptr<Env> copy = spec->NewEnv(Rng(999));
  copy->Reset(walk);
  ASSERT_TRUE(copy->Restore(*snapshot).ok());
  EXPECT_TRUE(snapshot->physics.Equals(copy->data()));
  EXPECT_EQ(copy->steps(), original->steps());
  // A juggle cycle of the 1.4 m apex is about 43 control steps; the kick (about 14 steps from
  // here) is in it. The upper body (the first 14 actions: chest, neck, arms) moves randomly.
  EXPECT_GE(ExpectSameFuture(*spec, original.get(), copy.get(), 50, 14), 43);
}

TEST(EnvSnapshotTest, SoccerRestoreRewindsTheSameEnv) {
  const std::shared_ptr<const EnvSpec> spec = LoadFamilySpec("right_foot_recipe");
  ASSERT_NE(spec, nullptr);
  const AdaptiveWalk walk(&spec->graph());
  std::unique_ptr<Env> env = spec->NewEnv(Rng(6));
  env->Reset(walk);
  std::unique_ptr<EnvSnapshot> start = env->Snapshot();
  const std::vector<float> zero(spec->act_dim(), 0.0f);
  std::vector<double> first_run;
  for (int t = 0; t < 30; ++t) {
    env->Step(zero.data(), walk);
    first_run.push_back(env->data()->qpos[2]);
  }
  ASSERT_TRUE(env->Restore(*start).ok());
  EXPECT_EQ(env->steps(), 0);
  for (int t = 0; t < 30; ++t) {
    env->Step(zero.data(), walk);
    ASSERT_EQ(env->data()->qpos[2], first_run[t]) << "step " << t;
  }
}

TEST(EnvSnapshotTest, TossTaskCopyStepsBitForBit) {
  for (const char* name : {"toss_catch", "toss_throw"}) {
    SCOPED_TRACE(name);
    const std::shared_ptr<const EnvSpec> spec = LoadFamilySpec(name);
    ASSERT_NE(spec, nullptr);
    const AdaptiveWalk walk(&spec->graph());
    std::unique_ptr<Env> original = spec->NewEnv(Rng(8));
    original->Reset(walk);
    const std::vector<float> zero(spec->act_dim(), 0.0f);
    for (int t = 0; t < 3; ++t) original->Step(zero.data(), walk);
    std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
    ASSERT_NE(snapshot, nullptr);
    EXPECT_EQ(snapshot->family(), "toss");
    std::unique_ptr<Env> copy = spec->NewEnv(Rng(1234));
    copy->Reset(walk);
    ASSERT_TRUE(copy->Restore(*snapshot).ok());
    EXPECT_GE(ExpectSameFuture(*spec, original.get(), copy.get(), 60, spec->act_dim()), 20);
  }
}

TEST(EnvSnapshotTest, RefusesASnapshotOfAnotherFamily) {
  const std::shared_ptr<const EnvSpec> soccer = LoadFamilySpec("right_foot_recipe");
  const std::shared_ptr<const EnvSpec> toss = LoadFamilySpec("toss_catch");
  ASSERT_NE(soccer, nullptr);
  ASSERT_NE(toss, nullptr);
  const AdaptiveWalk soccer_walk(&soccer->graph()), toss_walk(&toss->graph());
  std::unique_ptr<Env> soccer_env = soccer->NewEnv(Rng(1));
  std::unique_ptr<Env> toss_env = toss->NewEnv(Rng(1));
  soccer_env->Reset(soccer_walk);
  toss_env->Reset(toss_walk);
  PhysicsSnapshot before;
  before.Save(soccer->model(), soccer_env->data());
  const absl::Status s = soccer_env->Restore(*toss_env->Snapshot());
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "a snapshot of a toss env cannot be restored into a soccer_juggle env");
  EXPECT_TRUE(before.Equals(soccer_env->data())) << "a refused restore changed the env";
  const absl::Status t = toss_env->Restore(*soccer_env->Snapshot());
  EXPECT_EQ(t.code(), absl::StatusCode::kInvalidArgument);
}

TEST(EnvSnapshotTest, RefusesASnapshotOfAnotherModelOrConfig) {
  // Same family, another config (the paper's reference without the base controller).
  const std::shared_ptr<const EnvSpec> recipe = LoadFamilySpec("right_foot_recipe");
  const std::shared_ptr<const EnvSpec> paper = LoadFamilySpec("right_foot_paper");
  ASSERT_NE(recipe, nullptr);
  ASSERT_NE(paper, nullptr);
  EXPECT_NE(recipe->fingerprint(), paper->fingerprint());
  const AdaptiveWalk walk(&recipe->graph());
  std::unique_ptr<Env> a = recipe->NewEnv(Rng(1));
  std::unique_ptr<Env> b = paper->NewEnv(Rng(1));
  a->Reset(walk);
  b->Reset(AdaptiveWalk(&paper->graph()));
  const absl::Status s = a->Restore(*b->Snapshot());
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("another model or config"), std::string::npos) << s;
  // Two specs built from the same config are equal: their snapshots are interchangeable.
  const std::shared_ptr<const EnvSpec> recipe_again = LoadFamilySpec("right_foot_recipe");
  EXPECT_EQ(recipe->fingerprint(), recipe_again->fingerprint());
  std::unique_ptr<Env> c = recipe_again->NewEnv(Rng(2));
  EXPECT_TRUE(c->Restore(*a->Snapshot()).ok());
}

TEST(EnvSnapshotTest, DifferentModelsHaveDifferentFingerprints) {
  const std::shared_ptr<const EnvSpec> soccer = LoadFamilySpec("right_foot_recipe");
  const std::shared_ptr<const EnvSpec> toss = LoadFamilySpec("toss_catch");
  ASSERT_NE(soccer, nullptr);
  ASSERT_NE(toss, nullptr);
  EXPECT_NE(ModelFingerprint(soccer->model()), ModelFingerprint(toss->model()));
  EXPECT_EQ(ModelFingerprint(soccer->model()), ModelFingerprint(soccer->model()));
}

}  // namespace
}  // namespace juggle
