#include "learner/worker_registry.h"

#include <algorithm>
#include <set>

#include "absl/strings/str_cat.h"

namespace juggle {

namespace {

bool PrintableAscii(const std::string& s) {
  for (char c : s) {
    if (c < 0x21 || c > 0x7e) return false;
  }
  return true;
}

}  // namespace

absl::StatusOr<WorkerInfo> WorkerRegistry::Register(int requested_slot, int num_envs,
                                                    const std::string& host,
                                                    Clock::time_point now,
                                                    std::optional<uint64_t>* replaced,
                                                    int64_t sessions_before) {
  replaced->reset();
  if (requested_slot < -1 || requested_slot >= limits_.max_workers) {
    return absl::InvalidArgumentError(absl::StrCat("register: slot ", requested_slot,
                                                   " is outside [-1, ", limits_.max_workers,
                                                   ") (service.max_workers)"));
  }
  if (num_envs < 1 || num_envs > limits_.max_envs_per_worker) {
    return absl::InvalidArgumentError(absl::StrCat("register: num_envs ", num_envs,
                                                   " is outside [1, ", limits_.max_envs_per_worker,
                                                   "] (service.max_envs_per_worker)"));
  }
  if (host.empty() || host.size() > RegistryLimits::kMaxHostBytes || !PrintableAscii(host)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "register: the host name must be 1-", RegistryLimits::kMaxHostBytes,
        " printable ASCII characters (got ", host.size(), " bytes)"));
  }
  std::lock_guard<std::mutex> lock(mu_);
  std::set<int> used;
  int on_host = 0;
  std::optional<uint64_t> holder;  // the incarnation holding the requested slot
  for (const auto& [inc, w] : by_incarnation_) {
    used.insert(w.slot);
    if (w.slot == requested_slot) holder = inc;
    else if (w.host == host) ++on_host;
  }
  const int others = static_cast<int>(by_incarnation_.size()) - (holder ? 1 : 0);
  if (others >= limits_.max_workers) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "register: ", others, " workers are live, the limit (service.max_workers)"));
  }
  if (on_host >= limits_.max_workers_per_host) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "register: ", on_host, " workers of host ", host,
        " are live, the limit (service.max_workers_per_host)"));
  }
  int slot = requested_slot;
  if (slot < 0) {
    slot = 0;
    while (used.count(slot)) ++slot;
  } else if (holder) {
    *replaced = *holder;
    by_incarnation_.erase(*holder);
  }
  WorkerInfo info;
  info.slot = slot;
  info.incarnation = next_incarnation_++;
  info.num_envs = num_envs;
  info.host = host;
  info.last_seen = now;
  info.sessions = std::clamp<int64_t>(sessions_before, 0, int64_t{1} << 40) + 1;
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

void WorkerRegistry::CountChunk(uint64_t incarnation, bool accepted, int64_t policy_version) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = by_incarnation_.find(incarnation);
  if (it == by_incarnation_.end()) return;
  ++(accepted ? it->second.chunks_accepted : it->second.chunks_rejected);
  it->second.newest_chunk_version = std::max(it->second.newest_chunk_version, policy_version);
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
