#include "common/fork_join_pool.h"

#include "common/check.h"

namespace juggle {

ForkJoinPool::ForkJoinPool(int threads) {
  JUGGLE_CHECK(threads >= 1, "a fork-join pool needs a thread");
  workers_.reserve(threads - 1);
  for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { WorkerMain(t); });
}

ForkJoinPool::~ForkJoinPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ForkJoinPool::Drain(int n, const Job& job, int thread) {
  for (int i = next_.fetch_add(1); i < n; i = next_.fetch_add(1)) job(i, thread);
}

void ForkJoinPool::WorkerMain(int thread) {
  int64_t seen = 0;
  while (true) {
    const Job* job;
    int n;
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      job = job_;
      n = n_;
    }
    Drain(n, *job, thread);
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (--running_ == 0) done_cv_.notify_one();
    }
  }
}

void ForkJoinPool::Run(int n, Job job) {
  if (n <= 0) return;
  if (workers_.empty()) {
    for (int i = 0; i < n; ++i) job(i, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    // Every pool thread left the previous generation before its Run returned: none reads next_.
    next_.store(0);
    job_ = &job;
    n_ = n;
    running_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  start_cv_.notify_all();
  Drain(n, job, 0);
  std::unique_lock<std::mutex> lock(mu_);
  done_cv_.wait(lock, [&] { return running_ == 0; });
  job_ = nullptr;
}

}  // namespace juggle
