// A bounded FIFO queue with deadlines: the learner's ingestion flow control. Push blocks while
// the queue is full (so a slow learner slows its producers) and gives up at the deadline; Pop
// blocks while it is empty. Close() wakes everyone: pushes then fail and pops drain what is
// left. Thread-safe.
#ifndef JUGGLE_COMMON_BOUNDED_QUEUE_H_
#define JUGGLE_COMMON_BOUNDED_QUEUE_H_

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

namespace juggle {

template <typename T>
class BoundedQueue {
 public:
  using Clock = std::chrono::steady_clock;
  explicit BoundedQueue(size_t capacity) : capacity_(capacity) {}

  // False if the deadline passed while full, or the queue is closed.
  bool Push(T item, Clock::time_point deadline) {
    std::unique_lock<std::mutex> lock(mu_);
    if (!not_full_.wait_until(lock, deadline, [&] { return closed_ || items_.size() < capacity_; }) ||
        closed_) {
      return false;
    }
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return true;
  }

  // Empty optional if the deadline passed while empty, or the queue is closed and drained.
  std::optional<T> Pop(Clock::time_point deadline) {
    std::unique_lock<std::mutex> lock(mu_);
    if (!not_empty_.wait_until(lock, deadline, [&] { return closed_ || !items_.empty(); }) ||
        items_.empty()) {
      return std::nullopt;
    }
    T item = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return item;
  }

  void Close() {
    std::lock_guard<std::mutex> lock(mu_);
    closed_ = true;
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  size_t size() const {
    std::lock_guard<std::mutex> lock(mu_);
    return items_.size();
  }
  size_t capacity() const { return capacity_; }

 private:
  const size_t capacity_;
  mutable std::mutex mu_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  bool closed_ = false;
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_BOUNDED_QUEUE_H_
