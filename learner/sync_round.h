// Which workers a synchronous round waits for. A round (one policy version) waits for every
// live slot; once `timeout_s` has passed since the round began and at least one slot has
// delivered, the slots still missing are benched: later rounds go on without them until they
// deliver a contribution of the current version, which brings them back. So a worker that
// registers and sends nothing delays training by at most one timeout, not until it is
// forgotten. Thread-compatible (the training thread's).
#ifndef JUGGLE_LEARNER_SYNC_ROUND_H_
#define JUGGLE_LEARNER_SYNC_ROUND_H_

#include <chrono>
#include <cstdint>
#include <set>
#include <vector>

namespace juggle {

class SyncRound {
 public:
  using Clock = std::chrono::steady_clock;

  // Called before every attempt to take the batch of `version`. `missing`: the live slots
  // without a complete contribution of `version`. Returns the slots benched by this call.
  // timeout_s <= 0: never bench.
  std::vector<int> Update(int64_t version, Clock::time_point now, double timeout_s,
                          const std::vector<int>& live_slots, const std::vector<int>& missing);
  // The slots of `live_slots` the round waits for (the benched ones left out).
  std::vector<int> Required(const std::vector<int>& live_slots) const;
  const std::set<int>& benched() const { return benched_; }

 private:
  int64_t version_ = -1;
  Clock::time_point start_;
  std::set<int> benched_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_SYNC_ROUND_H_
