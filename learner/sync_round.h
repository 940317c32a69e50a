// Which workers a synchronous round waits for. A round (one policy version) waits for every
// live slot; once `timeout_s` has passed since the round began and at least one slot has
// delivered, the slots still missing are benched: later rounds go on without them until they
// deliver a contribution of the current version, or send any chunk (even one refused as
// stale) of the version they were benched in or newer: that shows the worker keeps up with the
// rounds but finishes each just after the others, so it would never catch up unless a round
// waits for it again. A readmitted slot gets a full timeout from its readmission. So a worker
// that registers and sends nothing delays training by at most one timeout, not until it is
// forgotten. Thread-compatible (the training thread's).
#ifndef JUGGLE_LEARNER_SYNC_ROUND_H_
#define JUGGLE_LEARNER_SYNC_ROUND_H_

#include <chrono>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

namespace juggle {

class SyncRound {
 public:
  using Clock = std::chrono::steady_clock;

  // Called before every attempt to take the batch of `version`. `missing`: the live slots
  // without a complete contribution of `version`. `newest_sent`: per slot, the newest policy
  // version of any chunk it sent, accepted or not (slots absent: none). Returns the slots
  // benched by this call. timeout_s <= 0: never bench.
  std::vector<int> Update(int64_t version, Clock::time_point now, double timeout_s,
                          const std::vector<int>& live_slots, const std::vector<int>& missing,
                          const std::map<int, int64_t>& newest_sent = {});
  // The slots of `live_slots` the round waits for (the benched ones left out).
  std::vector<int> Required(const std::vector<int>& live_slots) const;
  std::set<int> benched() const;

 private:
  int64_t version_ = -1;
  Clock::time_point start_;
  std::map<int, int64_t> benched_;                 // slot -> the version it was benched in
  std::map<int, Clock::time_point> readmitted_;    // slot -> when it was readmitted
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_SYNC_ROUND_H_
