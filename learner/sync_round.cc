#include "learner/sync_round.h"

#include <algorithm>

namespace juggle {

std::vector<int> SyncRound::Update(int64_t version, Clock::time_point now, double timeout_s,
                                   const std::vector<int>& live_slots,
                                   const std::vector<int>& missing) {
  if (version != version_) {
    version_ = version;
    start_ = now;
  }
  const std::set<int> live(live_slots.begin(), live_slots.end());
  const std::set<int> absent(missing.begin(), missing.end());
  // Back in: slots that delivered, and slots no longer live (a new worker there starts fresh).
  for (auto it = benched_.begin(); it != benched_.end();) {
    it = (!live.count(*it) || !absent.count(*it)) ? benched_.erase(it) : std::next(it);
  }
  std::vector<int> newly;
  const bool someone_delivered = absent.size() < live.size();
  if (timeout_s > 0 && someone_delivered &&
      std::chrono::duration<double>(now - start_).count() > timeout_s) {
    for (int slot : missing) {
      if (benched_.insert(slot).second) newly.push_back(slot);
    }
  }
  return newly;
}

std::vector<int> SyncRound::Required(const std::vector<int>& live_slots) const {
  std::vector<int> required;
  for (int slot : live_slots) {
    if (!benched_.count(slot)) required.push_back(slot);
  }
  return required;
}

}  // namespace juggle
