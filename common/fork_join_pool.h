// ForkJoinPool: runs the jobs 0..n-1 of one call on T threads, the caller's included, and
// returns when all of them have returned. Threads take the next job index from a shared counter,
// so which thread runs a job is not fixed: a caller that wants the same results whatever T is
// must make a job's result depend only on its index (and per-thread state it resets itself).
// The T - 1 pool threads are started once and sleep between calls (one generation per call).
//
// Thread-safety: Run must be called from one thread at a time, never from inside a job; the
// jobs of one call run concurrently with each other.
#ifndef JUGGLE_COMMON_FORK_JOIN_POOL_H_
#define JUGGLE_COMMON_FORK_JOIN_POOL_H_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/functional/function_ref.h"

namespace juggle {

class ForkJoinPool {
 public:
  // job(index, thread): `thread` in [0, threads()) names the thread running it (0: the
  // caller), for per-thread scratch state. Not owning, so a call allocates nothing.
  using Job = absl::FunctionRef<void(int index, int thread)>;

  // REQUIRES: threads >= 1. Starts threads - 1 pool threads.
  explicit ForkJoinPool(int threads);
  // Joins the pool threads. REQUIRES: no Run in progress.
  ~ForkJoinPool();
  ForkJoinPool(const ForkJoinPool&) = delete;
  ForkJoinPool& operator=(const ForkJoinPool&) = delete;

  // Calls job(i, thread) exactly once for every i in [0, n), on the caller's thread and the
  // pool's; returns when every call has returned (n <= 0: at once, calling nothing). With one
  // thread the jobs run in index order on the caller's thread, without locking.
  // REQUIRES: not called concurrently, nor from inside a job.
  void Run(int n, Job job);

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

 private:
  void WorkerMain(int thread);
  // Runs jobs of the current generation until no index is left.
  void Drain(int n, const Job& job, int thread);

  std::vector<std::thread> workers_;  // thread t is workers_[t - 1]

  std::mutex mu_;
  std::condition_variable start_cv_;  // generation_ advanced, or stop_
  std::condition_variable done_cv_;   // running_ reached 0
  int64_t generation_ ABSL_GUARDED_BY(mu_) = 0;
  int running_ ABSL_GUARDED_BY(mu_) = 0;  // pool threads still in the current generation
  bool stop_ ABSL_GUARDED_BY(mu_) = false;
  // The current call, set by Run before its generation starts (`job_` points to Run's
  // argument).
  const Job* job_ ABSL_GUARDED_BY(mu_) = nullptr;
  int n_ ABSL_GUARDED_BY(mu_) = 0;
  // The next job index to take. Reset only while no pool thread is in a generation.
  std::atomic<int> next_{0};
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_FORK_JOIN_POOL_H_
