#include "play/frame_hub.h"

#include <algorithm>

namespace juggle::play {

FrameHub::FrameHub(int max_viewers, int queue_capacity)
    : max_viewers_(max_viewers), capacity_(static_cast<size_t>(std::max(1, queue_capacity))) {}

std::optional<int64_t> FrameHub::Join() {
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_ || static_cast<int>(viewers_.size()) >= max_viewers_) return std::nullopt;
  const int64_t id = next_id_++;
  viewers_[id] = std::make_shared<Viewer>();
  return id;
}

void FrameHub::Leave(int64_t viewer) {
  std::lock_guard<std::mutex> lock(mu_);
  viewers_.erase(viewer);
}

void FrameHub::Push(Viewer* viewer, const std::string& message) {
  if (viewer->queue.size() >= capacity_) {
    viewer->queue.pop_front();
    ++dropped_;
  }
  viewer->queue.push_back(message);
}

void FrameHub::Publish(const std::string& message) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    ++published_;
    for (auto& [id, viewer] : viewers_) Push(viewer.get(), message);
  }
  cv_.notify_all();
}

void FrameHub::SendTo(int64_t viewer, const std::string& message) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    auto it = viewers_.find(viewer);
    if (it == viewers_.end()) return;
    Push(it->second.get(), message);
  }
  cv_.notify_all();
}

std::optional<std::string> FrameHub::Take(int64_t viewer, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mu_);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (closed_) return std::nullopt;
    auto it = viewers_.find(viewer);
    if (it == viewers_.end()) return std::nullopt;
    if (!it->second->queue.empty()) {
      std::string message = std::move(it->second->queue.front());
      it->second->queue.pop_front();
      return message;
    }
    if (cv_.wait_until(lock, deadline) == std::cv_status::timeout) return std::nullopt;
  }
}

void FrameHub::Close() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

int FrameHub::viewers() const {
  std::lock_guard<std::mutex> lock(mu_);
  return static_cast<int>(viewers_.size());
}

bool FrameHub::has_viewer(int64_t viewer) const {
  std::lock_guard<std::mutex> lock(mu_);
  return viewers_.count(viewer) > 0;
}

bool FrameHub::closed() const {
  std::lock_guard<std::mutex> lock(mu_);
  return closed_;
}

int64_t FrameHub::dropped() const {
  std::lock_guard<std::mutex> lock(mu_);
  return dropped_;
}

int64_t FrameHub::published() const {
  std::lock_guard<std::mutex> lock(mu_);
  return published_;
}

}  // namespace juggle::play
