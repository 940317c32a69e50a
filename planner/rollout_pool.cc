#include "planner/rollout_pool.h"

#include "common/check.h"

namespace juggle {

RolloutPool::RolloutPool(std::shared_ptr<const EnvSpec> spec, int threads,
                         std::shared_ptr<const EnvSpec> twin_spec)
    : spec_(std::move(spec)), pool_(threads) {  // pool_ checks threads >= 1
  JUGGLE_CHECK(twin_spec == nullptr || twin_spec->fingerprint() == spec_->fingerprint(),
               "a twin spec must take the pool spec's snapshots");
  for (int t = 0; t < threads; ++t) envs_.push_back(spec_->NewEnv(Rng(0)));
  if (twin_spec != nullptr) {
    for (int t = 0; t < threads; ++t) twins_.push_back(twin_spec->NewEnv(Rng(0)));
  }
}

Env* RolloutPool::TwinOf(const Env* env) const {
  for (size_t t = 0; t < twins_.size(); ++t) {
    if (envs_[t].get() == env) return twins_[t].get();
    if (twins_[t].get() == env) return envs_[t].get();
  }
  return nullptr;
}

RolloutPool::~RolloutPool() = default;

absl::Status RolloutPool::Run(const EnvSnapshot& snapshot, int n,
                              const std::function<void(int, Env*)>& fn) {
  if (absl::Status s = envs_[0]->Restore(snapshot); !s.ok()) return s;
  pool_.Run(n, [&](int i, int thread) {
    // Every call starts from the snapshot, whichever thread's env runs it. It restored into
    // envs_[0] above already: it matches.
    Env* env = envs_[thread].get();
    const absl::Status restored = env->Restore(snapshot);
    JUGGLE_CHECK(restored.ok(), "a snapshot that restored once failed to restore again");
    fn(i, env);
  });
  return absl::OkStatus();
}

}  // namespace juggle
