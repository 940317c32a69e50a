#include "planner/rollout_pool.h"

#include "common/check.h"

namespace juggle {

RolloutPool::RolloutPool(std::shared_ptr<const EnvSpec> spec, int threads)
    : spec_(std::move(spec)) {
  JUGGLE_CHECK(threads >= 1, "a rollout pool needs a thread");
  for (int t = 0; t < threads; ++t) envs_.push_back(spec_->NewEnv(Rng(0)));
  for (int t = 1; t < threads; ++t) threads_.emplace_back([this, t] { ThreadMain(t); });
}

RolloutPool::~RolloutPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void RolloutPool::Work(int thread) {
  Env* env = envs_[thread].get();
  for (int i = next_.fetch_add(1); i < n_; i = next_.fetch_add(1)) {
    // The snapshot was restored into envs_[0] by Run already: it matches.
    const absl::Status restored = env->Restore(*snapshot_);
    JUGGLE_CHECK(restored.ok(), "a snapshot that restored once failed to restore again");
    (*fn_)(i, env);
  }
}

void RolloutPool::ThreadMain(int thread) {
  int seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    Work(thread);
    {
      std::lock_guard<std::mutex> lock(mu_);
      --running_;
    }
    done_cv_.notify_one();
  }
}

absl::Status RolloutPool::Run(const EnvSnapshot& snapshot, int n,
                              const std::function<void(int, Env*)>& fn) {
  if (absl::Status s = envs_[0]->Restore(snapshot); !s.ok()) return s;
  snapshot_ = &snapshot;
  fn_ = &fn;
  n_ = n;
  next_.store(0);
  {
    std::lock_guard<std::mutex> lock(mu_);
    running_ = static_cast<int>(threads_.size());
    ++generation_;
  }
  start_cv_.notify_all();
  Work(0);
  std::unique_lock<std::mutex> lock(mu_);
  done_cv_.wait(lock, [&] { return running_ == 0; });
  return absl::OkStatus();
}

}  // namespace juggle
