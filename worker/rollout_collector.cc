#include "worker/rollout_collector.h"

#include <algorithm>

#include "absl/cleanup/cleanup.h"
#include "common/status_macros.h"

namespace juggle {
namespace {

// Salt separating action-noise streams from the env streams of the same (seed, worker, env).
constexpr uint64_t kActionStreamSalt = 0x5DEECE66DULL;
// And the expert's action noise from both.
constexpr uint64_t kExpertStreamSalt = 0x2545F4914F6CDD1DULL;

}  // namespace

RolloutCollector::RolloutCollector(EnvPool* pool, int unroll_length, uint64_t seed,
                                   uint64_t worker)
    : pool_(pool), unroll_length_(unroll_length) {
  for (int i = 0; i < pool->num_envs(); ++i) {
    rngs_.push_back(Rng::ForStream(seed ^ kActionStreamSalt, worker, i));
  }
  actions_.resize(size_t(pool->num_envs()) * pool->act_dim());
  for (int i = 0; i < pool->num_envs(); ++i) {
    expert_rngs_.push_back(Rng::ForStream(seed ^ kExpertStreamSalt, worker, i));
  }
}

void RolloutCollector::set_label_plan(const LabelPlan& plan) {
  labels_ = plan;
  if (labels_.labeller == nullptr) labels_.label_envs = labels_.expert_envs = 0;
  pool_->set_separate_envs(labels_.expert_envs);
}

absl::Status RolloutCollector::Collect(const EigenPolicy& policy, UnrollBatch* batch,
                                       std::vector<EdgeEvent>* events,
                                       std::vector<int32_t>* nodes) {
  // The labeller sees the acting policy for this unroll's labels, and none after it.
  if (labels_.labeller != nullptr) RETURN_IF_ERROR(labels_.labeller->SetPolicy(&policy));
  absl::Cleanup forget = [this] {
    if (labels_.labeller != nullptr) labels_.labeller->SetPolicy(nullptr).IgnoreError();
  };
  if (!started_) {
    pool_->Reset();
    started_ = true;
  }
  const int U = pool_->num_envs(), T = unroll_length_, D = pool_->obs_dim(),
            A = pool_->act_dim();
  batch->num_unrolls = U;
  batch->unroll_length = T;
  batch->obs_dim = D;
  batch->act_dim = A;
  batch->obs.resize(size_t(U) * T * D);
  batch->actions.resize(size_t(U) * T * A);
  batch->log_probs.resize(size_t(U) * T);
  batch->rewards.resize(size_t(U) * T);
  batch->done.assign(size_t(U) * T, 0);
  batch->truncated.assign(size_t(U) * T, 0);
  batch->truncated_obs.clear();
  batch->bootstrap_obs.resize(size_t(U) * D);
  batch->policy_version.assign(U, policy.version());
  if (nodes != nullptr) nodes->assign(size_t(U) * T, 0);
  const int L = labels_.label_envs;
  batch->labelled.assign(L > 0 ? U : 0, 0);
  batch->expert_driven.assign(L > 0 ? U : 0, 0);
  batch->labels.resize(size_t(L) * T * A);
  for (int u = 0; u < L; ++u) {
    batch->labelled[u] = 1;
    batch->expert_driven[u] = u < labels_.expert_envs;
  }

  // Truncated final observations arrive step by step but must be stored in (u, t) order.
  std::vector<std::vector<float>> truncated_per_env(U);
  for (int t = 0; t < T; ++t) {
    if (stop_ != nullptr && stop_->load()) return absl::CancelledError("stopped mid-unroll");
    const PoolStep& out = pool_->output();
    const RowMatrix mean = policy.MeanActions(out.obs.data(), U);
    for (int u = 0; u < U; ++u) {
      const size_t i = size_t(u) * T + t;
      std::copy(out.obs.begin() + size_t(u) * D, out.obs.begin() + size_t(u + 1) * D,
                batch->obs.begin() + i * D);
      batch->log_probs[i] = policy.Sample(mean.row(u).data(), &rngs_[u],
                                          &actions_[size_t(u) * A]);
      if (u < L) {
        // Labelled unrolls are the first L, so unroll u's label rows start at u·T·A.
        float* label = &batch->labels[i * A];
        RETURN_IF_ERROR(labels_.labeller->Label(pool_->env(u), label));
        ++labels_since_take_;
        if (u < labels_.expert_envs) {
          // The expert acts (DART noise on top); the student's log-probability is not used
          // for such unrolls (they never reach PPO).
          for (int a = 0; a < A; ++a) {
            const double noise = labels_.expert_noise * expert_rngs_[u].Normal();
            actions_[size_t(u) * A + a] = std::clamp(float(label[a] + noise), -1.0f, 1.0f);
          }
          batch->log_probs[i] = 0;
        }
      }
      std::copy(actions_.begin() + size_t(u) * A,
                actions_.begin() + size_t(u + 1) * A,
                batch->actions.begin() + i * A);
    }
    pool_->Step(actions_.data());
    for (int u = 0; u < U; ++u) {
      const size_t i = size_t(u) * T + t;
      batch->rewards[i] = out.reward[u];
      if (nodes != nullptr) (*nodes)[i] = out.node[u];
      batch->done[i] = out.terminated[u];
      batch->truncated[i] = out.truncated[u];
      if (out.truncated[u]) {
        truncated_per_env[u].insert(truncated_per_env[u].end(),
                                    out.final_obs.begin() + size_t(u) * D,
                                    out.final_obs.begin() + size_t(u + 1) * D);
      }
    }
    if (events != nullptr) events->insert(events->end(), out.events.begin(), out.events.end());
  }
  for (const std::vector<float>& v : truncated_per_env) {
    batch->truncated_obs.insert(batch->truncated_obs.end(), v.begin(), v.end());
  }
  std::copy(pool_->output().obs.begin(), pool_->output().obs.end(), batch->bootstrap_obs.begin());
  return absl::OkStatus();
}

}  // namespace juggle

namespace juggle {

ExpertCounters RolloutCollector::TakeExpertCounters() {
  if (labels_.labeller == nullptr) return {};
  ExpertCounters c = labels_.labeller->TakeCounters();
  c.labels = labels_since_take_;
  labels_since_take_ = 0;
  return c;
}

}  // namespace juggle
