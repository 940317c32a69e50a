#include "learner/worker_registry.h"

#include <algorithm>
#include <set>

namespace juggle {

WorkerInfo WorkerRegistry::Register(int requested_slot, int num_envs, const std::string& host,
                                    Clock::time_point now, std::optional<uint64_t>* replaced) {
  std::lock_guard<std::mutex> lock(mu_);
  replaced->reset();
  std::set<int> used;
  for (const auto& [inc, w] : by_incarnation_) used.insert(w.slot);
  int slot = requested_slot;
  if (slot < 0) {
    slot = 0;
    while (used.count(slot)) ++slot;
  } else {
    for (auto it = by_incarnation_.begin(); it != by_incarnation_.end(); ++it) {
      if (it->second.slot == slot) {
        *replaced = it->first;
        by_incarnation_.erase(it);
        break;
      }
    }
  }
  WorkerInfo info;
  info.slot = slot;
  info.incarnation = next_incarnation_++;
  info.num_envs = num_envs;
  info.host = host;
  info.last_seen = now;
  by_incarnation_[info.incarnation] = info;
  return info;
}

bool WorkerRegistry::Touch(uint64_t incarnation, Clock::time_point now, int64_t policy_version,
                           double env_steps_per_s) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = by_incarnation_.find(incarnation);
  if (it == by_incarnation_.end()) return false;
  it->second.last_seen = now;
  if (policy_version >= 0) it->second.policy_version = policy_version;
  if (env_steps_per_s >= 0) it->second.env_steps_per_s = env_steps_per_s;
  return true;
}

std::optional<WorkerInfo> WorkerRegistry::Find(uint64_t incarnation) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = by_incarnation_.find(incarnation);
  if (it == by_incarnation_.end()) return std::nullopt;
  return it->second;
}

void WorkerRegistry::CountChunk(uint64_t incarnation, bool accepted) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = by_incarnation_.find(incarnation);
  if (it == by_incarnation_.end()) return;
  ++(accepted ? it->second.chunks_accepted : it->second.chunks_rejected);
}

std::vector<uint64_t> WorkerRegistry::Expire(Clock::time_point now,
                                             std::chrono::duration<double> timeout) {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<uint64_t> expired;
  for (auto it = by_incarnation_.begin(); it != by_incarnation_.end();) {
    if (now - it->second.last_seen > timeout) {
      expired.push_back(it->first);
      it = by_incarnation_.erase(it);
    } else {
      ++it;
    }
  }
  return expired;
}

void WorkerRegistry::Remove(uint64_t incarnation) {
  std::lock_guard<std::mutex> lock(mu_);
  by_incarnation_.erase(incarnation);
}

std::vector<WorkerInfo> WorkerRegistry::Live() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<WorkerInfo> live;
  for (const auto& [inc, w] : by_incarnation_) live.push_back(w);
  std::sort(live.begin(), live.end(), [](const WorkerInfo& a, const WorkerInfo& b) { return a.slot < b.slot; });
  return live;
}

}  // namespace juggle
