// The fork-join pool: every job once, the caller's thread taking part, results that do not
// depend on the thread count, many calls in a row, zero jobs, and joining on destruction.
#include "common/fork_join_pool.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "gtest/gtest.h"

namespace juggle {
namespace {

// Waits until `count` jobs have arrived, or 10 s; false on the timeout.
bool ArriveAndWait(std::atomic<int>* arrived, int count) {
  arrived->fetch_add(1);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (arrived->load() < count) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::yield();
  }
  return true;
}

TEST(ForkJoinPoolTest, RunsEveryIndexExactlyOnce) {
  for (int threads : {1, 2, 4}) {
    ForkJoinPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    constexpr int kJobs = 1000;
    std::vector<std::atomic<int>> calls(kJobs);
    std::vector<std::atomic<int>> slot(kJobs);
    pool.Run(kJobs, [&](int i, int thread) {
      calls[i].fetch_add(1);
      slot[i].store(thread);
    });
    for (int i = 0; i < kJobs; ++i) {
      EXPECT_EQ(calls[i].load(), 1) << "job " << i << " with " << threads << " threads";
      EXPECT_GE(slot[i].load(), 0);
      EXPECT_LT(slot[i].load(), threads);
    }
  }
}

TEST(ForkJoinPoolTest, RunsAsManyJobsAtOnceAsItHasThreadsTheCallersIncluded) {
  // Each of the three jobs waits for the other two: they finish only if the caller and both
  // pool threads each run one.
  ForkJoinPool pool(3);
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> arrived{0};
  std::vector<uint8_t> met(3, 0);
  std::vector<int> slot(3, -1);
  std::vector<std::thread::id> ran_on(3);
  pool.Run(3, [&](int i, int thread) {
    met[i] = ArriveAndWait(&arrived, 3);
    slot[i] = thread;
    ran_on[i] = std::this_thread::get_id();
  });
  int on_caller = 0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(met[i]) << "job " << i << " never saw the others run";
    // Slot 0 is the caller's thread, and only it.
    EXPECT_EQ(slot[i] == 0, ran_on[i] == caller) << "job " << i;
    on_caller += ran_on[i] == caller;
  }
  EXPECT_EQ(on_caller, 1);
  EXPECT_NE(slot[0], slot[1]);
  EXPECT_NE(slot[1], slot[2]);
  EXPECT_NE(slot[0], slot[2]);
}

TEST(ForkJoinPoolTest, OneThreadRunsTheJobsInOrderOnTheCaller) {
  ForkJoinPool pool(1);
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<int> order;
  pool.Run(5, [&](int i, int thread) {
    EXPECT_EQ(thread, 0);
    EXPECT_EQ(std::this_thread::get_id(), caller);
    order.push_back(i);
  });
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
}

// A job whose result depends only on its index, computed in per-thread scratch state that
// the job resets first (the way RolloutPool restores a snapshot into its thread's env).
std::vector<uint64_t> Hashes(int threads, int jobs) {
  ForkJoinPool pool(threads);
  std::vector<std::vector<uint64_t>> scratch(threads, std::vector<uint64_t>(64));
  std::vector<uint64_t> out(jobs);
  pool.Run(jobs, [&](int i, int thread) {
    std::vector<uint64_t>& s = scratch[thread];
    s.assign(s.size(), static_cast<uint64_t>(i));
    uint64_t h = 1469598103934665603ULL;
    for (int round = 0; round < 100; ++round) {
      for (uint64_t& v : s) {
        v = v * 6364136223846793005ULL + 1442695040888963407ULL;
        h = (h ^ v) * 1099511628211ULL;
      }
    }
    out[i] = h;
  });
  return out;
}

TEST(ForkJoinPoolTest, ResultsDoNotDependOnTheThreadCount) {
  const std::vector<uint64_t> one = Hashes(1, 257);
  EXPECT_EQ(Hashes(2, 257), one);
  EXPECT_EQ(Hashes(3, 257), one);
  EXPECT_EQ(Hashes(8, 257), one);
}

TEST(ForkJoinPoolTest, ManyCallsInARowEachRunTheirOwnJobs) {
  ForkJoinPool pool(3);
  for (int call = 0; call < 2000; ++call) {
    const int n = call % 7;  // 0 to 6 jobs: fewer, as many and more than threads
    std::vector<std::atomic<int>> calls(7);
    pool.Run(n, [&](int i, int) { calls[i].fetch_add(call + 1); });
    for (int i = 0; i < 7; ++i) {
      ASSERT_EQ(calls[i].load(), i < n ? call + 1 : 0) << "call " << call << ", job " << i;
    }
  }
}

TEST(ForkJoinPoolTest, ZeroOrNegativeJobsCallNothing) {
  for (int threads : {1, 3}) {
    ForkJoinPool pool(threads);
    std::atomic<int> calls{0};
    pool.Run(0, [&](int, int) { calls.fetch_add(1); });
    pool.Run(-2, [&](int, int) { calls.fetch_add(1); });
    EXPECT_EQ(calls.load(), 0);
    pool.Run(2, [&](int, int) { calls.fetch_add(1); });  // still usable
    EXPECT_EQ(calls.load(), 2);
  }
}

// Counts the pool threads that have exited: a thread_local's destructor runs at thread exit.
std::atomic<int> exited_threads{0};
struct CountsExit {
  bool armed = false;
  ~CountsExit() {
    if (armed) exited_threads.fetch_add(1);
  }
};
thread_local CountsExit counts_exit;

TEST(ForkJoinPoolTest, DestructionJoinsEveryPoolThread) {
  exited_threads.store(0);
  {
    ForkJoinPool pool(4);
    std::atomic<int> arrived{0};
    std::atomic<int> met{0};
    // Four jobs that wait for each other: every pool thread runs one and arms its counter.
    pool.Run(4, [&](int, int thread) {
      if (thread != 0) counts_exit.armed = true;
      met.fetch_add(ArriveAndWait(&arrived, 4));
    });
    ASSERT_EQ(met.load(), 4);
    EXPECT_EQ(exited_threads.load(), 0);
  }
  EXPECT_EQ(exited_threads.load(), 3);
}

TEST(ForkJoinPoolTest, DestructionWithoutAnyCallReturns) {
  ForkJoinPool pool(4);  // its threads are asleep, waiting for a first generation
}

}  // namespace
}  // namespace juggle
