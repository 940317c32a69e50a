// Simulates candidates in parallel: T threads (the caller's included), each with its own env of
// one spec, into which a snapshot is restored before every call. Results do not depend on
// which thread ran a call, so a search over the pool is deterministic whatever T is.
// Thread-safety: Run must be called from one thread at a time.
#ifndef JUGGLE_PLANNER_ROLLOUT_POOL_H_
#define JUGGLE_PLANNER_ROLLOUT_POOL_H_

#include <functional>
#include <memory>
#include <vector>

#include "absl/status/status.h"
#include "common/fork_join_pool.h"
#include "envs/env.h"

namespace juggle {

class RolloutPool {
 public:
  // REQUIRES: threads >= 1, `spec` owned by a shared_ptr. With `twin_spec` (a spec sharing
  // `spec`'s fingerprint: envs/planning_model.h), every thread's env has a twin of that spec,
  // into which a rollout can move its state on the way (TwinOf).
  RolloutPool(std::shared_ptr<const EnvSpec> spec, int threads,
              std::shared_ptr<const EnvSpec> twin_spec = nullptr);
  ~RolloutPool();
  RolloutPool(const RolloutPool&) = delete;
  RolloutPool& operator=(const RolloutPool&) = delete;

  // Calls fn(i, env) once for every i in [0, n), `env` holding `snapshot`'s state (restored
  // just before the call). Returns when every call has returned. Errors: the restore's
  // (INVALID_ARGUMENT for a snapshot of another family, model or config), before any call.
  absl::Status Run(const EnvSnapshot& snapshot, int n, const std::function<void(int, Env*)>& fn);

  int threads() const { return static_cast<int>(envs_.size()); }
  // The twin of one of this pool's envs, or the env of a twin (the same thread's); null
  // without twins or for an env of another pool. Only the thread running `env` may use it.
  Env* TwinOf(const Env* env) const;
  const EnvSpec& spec() const { return *spec_; }

 private:
  std::shared_ptr<const EnvSpec> spec_;
  std::vector<std::unique_ptr<Env>> envs_;  // one per pool thread; [0] is the caller's
  std::vector<std::unique_ptr<Env>> twins_;  // empty, or one per pool thread
  ForkJoinPool pool_;  // after envs_: destroyed (its threads joined) before them
};

}  // namespace juggle

#endif  // JUGGLE_PLANNER_ROLLOUT_POOL_H_
