#include "learner/broadcast_tracker.h"

#include <utility>

namespace juggle {

void BroadcastTracker::Published(int64_t version, Clock::time_point now,
                                 const std::vector<uint64_t>& workers) {
  if (workers.empty()) return;
  std::lock_guard<std::mutex> lock(mu_);
  pending_.push_back({version, now, std::set<uint64_t>(workers.begin(), workers.end())});
  while (pending_.size() > kMaxPending) pending_.pop_front();
}

std::vector<double> BroadcastTracker::Delivered(uint64_t incarnation, int64_t version,
                                                Clock::time_point now,
                                                const std::function<bool(uint64_t)>& is_live) {
  std::vector<double> done;
  std::lock_guard<std::mutex> lock(mu_);
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (it->version <= version) it->waiting.erase(incarnation);
    for (auto w = it->waiting.begin(); w != it->waiting.end();) {
      w = is_live(*w) ? std::next(w) : it->waiting.erase(w);
    }
    if (it->waiting.empty()) {
      // A version all its workers left without receiving was not broadcast: not measured.
      if (it->version <= version) {
        done.push_back(std::chrono::duration<double>(now - it->published).count());
      }
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  return done;
}

}  // namespace juggle
