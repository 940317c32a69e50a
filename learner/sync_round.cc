#include "learner/sync_round.h"

#include <algorithm>

namespace juggle {

std::vector<int> SyncRound::Update(int64_t version, Clock::time_point now, double timeout_s,
                                   const std::vector<int>& live_slots,
                                   const std::vector<int>& missing,
                                   const std::map<int, int64_t>& newest_sent) {
  if (version != version_) {
    version_ = version;
    start_ = now;
  }
  const std::set<int> live(live_slots.begin(), live_slots.end());
  const std::set<int> absent(missing.begin(), missing.end());
  for (auto it = readmitted_.begin(); it != readmitted_.end();) {
    it = live.count(it->first) ? std::next(it) : readmitted_.erase(it);
  }
  // Back in: slots that delivered, slots no longer live (a new worker there starts fresh), and
  // slots that sent a chunk of the version they were benched in or newer.
  for (auto it = benched_.begin(); it != benched_.end();) {
    const auto sent = newest_sent.find(it->first);
    const bool keeping_up = sent != newest_sent.end() && sent->second >= it->second;
    if (!live.count(it->first) || !absent.count(it->first)) {
      it = benched_.erase(it);
    } else if (keeping_up) {
      readmitted_[it->first] = now;
      it = benched_.erase(it);
    } else {
      ++it;
    }
  }
  std::vector<int> newly;
  const bool someone_delivered = absent.size() < live.size();
  if (timeout_s <= 0 || !someone_delivered) return newly;
  for (int slot : missing) {
    if (benched_.count(slot)) continue;
    const auto readmitted = readmitted_.find(slot);
    const Clock::time_point since =
        readmitted == readmitted_.end() ? start_ : std::max(start_, readmitted->second);
    if (std::chrono::duration<double>(now - since).count() > timeout_s) {
      benched_[slot] = version;
      readmitted_.erase(slot);
      newly.push_back(slot);
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

std::set<int> SyncRound::benched() const {
  std::set<int> slots;
  for (const auto& [slot, version] : benched_) slots.insert(slot);
  return slots;
}

}  // namespace juggle
