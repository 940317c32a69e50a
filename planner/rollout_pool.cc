#include "planner/rollout_pool.h"

#include "common/check.h"

namespace juggle {

RolloutPool::RolloutPool(std::shared_ptr<const EnvSpec> spec, int threads)
    : spec_(std::move(spec)), pool_(threads) {  // pool_ checks threads >= 1
  for (int t = 0; t < threads; ++t) envs_.push_back(spec_->NewEnv(Rng(0)));
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
