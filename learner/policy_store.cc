#include "learner/policy_store.h"

namespace juggle {

void PolicyStore::Publish(std::shared_ptr<const PolicySnapshot> snapshot) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    current_ = std::move(snapshot);
  }
  cv_.notify_all();
}

std::shared_ptr<const PolicySnapshot> PolicyStore::Current() const {
  std::lock_guard<std::mutex> lock(mu_);
  return current_;
}

std::shared_ptr<const PolicySnapshot> PolicyStore::WaitNewer(
    int64_t min_version, std::chrono::steady_clock::time_point deadline) const {
  std::unique_lock<std::mutex> lock(mu_);
  cv_.wait_until(lock, deadline, [&] {
    return closed_ || (current_ && current_->version > min_version);
  });
  return current_;
}

void PolicyStore::Close() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

}  // namespace juggle
