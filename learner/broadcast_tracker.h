// How long a new policy version takes to reach every worker: from its publication until each
// worker that was live then has received it (or a newer one) through GetPolicy. Workers that
// leave stop holding a version back. Thread-safe.
#ifndef JUGGLE_LEARNER_BROADCAST_TRACKER_H_
#define JUGGLE_LEARNER_BROADCAST_TRACKER_H_

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <set>
#include <vector>

namespace juggle {

class BroadcastTracker {
 public:
  using Clock = std::chrono::steady_clock;
  // Versions still on their way; beyond this many the oldest is given up (not measured).
  static constexpr size_t kMaxPending = 64;

  // `version` was published at `now` and must reach `workers` (incarnations). No workers: it
  // is not measured.
  void Published(int64_t version, Clock::time_point now, const std::vector<uint64_t>& workers);
  // `incarnation` received `version` at `now`; `is_live` says which incarnations still count
  // (the others are dropped from every pending version). Returns the broadcast times (seconds)
  // of the versions this completed, oldest first.
  std::vector<double> Delivered(uint64_t incarnation, int64_t version, Clock::time_point now,
                                const std::function<bool(uint64_t)>& is_live);

 private:
  struct Pending {
    int64_t version;
    Clock::time_point published;
    std::set<uint64_t> waiting;
  };
  std::mutex mu_;
  std::deque<Pending> pending_;  // oldest first
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_BROADCAST_TRACKER_H_
