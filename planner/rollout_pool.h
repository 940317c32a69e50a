// Simulates candidates in parallel: T threads (the caller's included), each with its own env of
// one spec, into which a snapshot is restored before every call. Results do not depend on
// which thread ran a call, so a search over the pool is deterministic whatever T is.
// Thread-safety: Run must be called from one thread at a time.
#ifndef JUGGLE_PLANNER_ROLLOUT_POOL_H_
#define JUGGLE_PLANNER_ROLLOUT_POOL_H_

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "envs/env.h"

namespace juggle {

class RolloutPool {
 public:
  // REQUIRES: threads >= 1, `spec` owned by a shared_ptr.
  RolloutPool(std::shared_ptr<const EnvSpec> spec, int threads);
  ~RolloutPool();
  RolloutPool(const RolloutPool&) = delete;
  RolloutPool& operator=(const RolloutPool&) = delete;

  // Calls fn(i, env) once for every i in [0, n), `env` holding `snapshot`'s state (restored
  // just before the call). Returns when every call has returned. Errors: the restore's
  // (INVALID_ARGUMENT for a snapshot of another family, model or config), before any call.
  absl::Status Run(const EnvSnapshot& snapshot, int n, const std::function<void(int, Env*)>& fn);

  int threads() const { return static_cast<int>(envs_.size()); }
  const EnvSpec& spec() const { return *spec_; }

 private:
  void ThreadMain(int thread);
  // Takes indices until none are left.
  void Work(int thread);

  std::shared_ptr<const EnvSpec> spec_;
  std::vector<std::unique_ptr<Env>> envs_;  // one per thread; [0] is the caller's
  std::vector<std::thread> threads_;

  std::mutex mu_;
  std::condition_variable start_cv_, done_cv_;
  int generation_ ABSL_GUARDED_BY(mu_) = 0;
  int running_ ABSL_GUARDED_BY(mu_) = 0;
  bool stop_ ABSL_GUARDED_BY(mu_) = false;
  // The current job (written by Run before a generation starts, read by the threads).
  const EnvSnapshot* snapshot_ = nullptr;
  const std::function<void(int, Env*)>* fn_ = nullptr;
  int n_ = 0;
  std::atomic<int> next_{0};
};

}  // namespace juggle

#endif  // JUGGLE_PLANNER_ROLLOUT_POOL_H_
