// The env pool: stepping many envs on several threads, counting episode ends, determinism.
#include "worker/env_pool.h"

#include <cmath>
#include <cstring>
#include <vector>

#include "envs/soccer_juggle/spec.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

class EnvPoolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = testing::LoadSpec("right_foot");
    ASSERT_NE(spec_, nullptr);
  }
  std::shared_ptr<const JuggleSpec> spec_;
};

TEST_F(EnvPoolTest, HugeTorquesDivergeAndAreCountedByThePool) {
  auto pool = EnvPool::Create(spec_, 2, 1, 5);
  ASSERT_TRUE(pool.ok());
  (*pool)->Reset();
  (*pool)->env(0).data()->qvel[20] = 1e30;  // blows up the integrator on the next step
  std::vector<float> actions(2 * kNumActions, 0.0f);
  (*pool)->Step(actions.data());
  EXPECT_EQ((*pool)->output().outcome[0], Outcome::kDiverged);
  EXPECT_EQ((*pool)->output().terminated[0], 1);
  for (float v : (*pool)->output().obs) ASSERT_TRUE(std::isfinite(v));
  const EpisodeCounters stats = (*pool)->TakeStats();
  EXPECT_EQ(stats.outcome(static_cast<int>(Outcome::kDiverged)), 1);
  EXPECT_EQ(stats.episodes, 1);
}

// Runs `steps` pool steps with seeded random actions; returns the concatenated observations.
std::vector<float> Rollout(std::shared_ptr<const JuggleSpec> spec, uint64_t seed, int threads,
                           int steps) {
  auto pool = EnvPool::Create(spec, 6, threads, seed);
  EXPECT_TRUE(pool.ok());
  Rng rng(99);
  std::vector<float> actions(6 * kNumActions);
  std::vector<float> trace;
  (*pool)->Reset();
  for (int s = 0; s < steps; ++s) {
    for (float& a : actions) a = static_cast<float>(rng.Uniform(-1, 1));
    (*pool)->Step(actions.data());
    const auto& obs = (*pool)->output().obs;
    trace.insert(trace.end(), obs.begin(), obs.end());
  }
  for (double c : (*pool)->walk()->counts()) trace.push_back(static_cast<float>(c));
  return trace;
}

TEST_F(EnvPoolTest, SameSeedGivesBitIdenticalTrajectoriesWhateverTheThreadCount) {
  const std::vector<float> a = Rollout(spec_, 42, 1, 60);
  const std::vector<float> b = Rollout(spec_, 42, 2, 60);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
}

TEST_F(EnvPoolTest, DifferentSeedsGiveDifferentTrajectories) {
  // Variable-height juggling draws from the env RNG at every cycle.
  auto spec = testing::LoadSpec("foot_variable_height");
  ASSERT_NE(spec, nullptr);
  const std::vector<float> a = Rollout(spec, 1, 2, 60);
  const std::vector<float> b = Rollout(spec, 2, 2, 60);
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace juggle
