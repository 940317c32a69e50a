// Test helpers: a point mass that must reach the origin (a small continuous-control problem
// written for the tests) and a collector that turns it into UnrollBatches.
#ifndef JUGGLE_LEARNER_TESTING_POINT_MASS_H_
#define JUGGLE_LEARNER_TESTING_POINT_MASS_H_

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/eigen_policy.h"
#include "common/rng.h"
#include "common/unroll_batch.h"
#include "learner/ppo_trainer.h"

namespace juggle::testing {

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

inline config::ModelConfig SmallModel() {
  config::ModelConfig m;
  m.set_num_experts(4);
  m.add_hidden(64);
  m.add_hidden(64);
  m.add_gate_hidden(32);
  m.add_gate_hidden(32);
  m.set_log_std(-1.0);
  return m;
}

inline config::PpoConfig SmallPpo() {
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
inline double Collect(const PpoTrainer& trainer, std::vector<PointMass>* envs, Rng* rng,
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

}  // namespace juggle::testing

#endif  // JUGGLE_LEARNER_TESTING_POINT_MASS_H_
