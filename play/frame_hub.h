// The live page's viewers and what each is sent (play/play_server.h): one bounded queue of
// messages per viewer. Publishing never blocks: a viewer whose queue is full loses its oldest
// message (a slow viewer drops frames; the simulation does not wait). Thread-safe: the
// simulation thread publishes while request threads take.
#ifndef JUGGLE_PLAY_FRAME_HUB_H_
#define JUGGLE_PLAY_FRAME_HUB_H_

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace juggle::play {

class FrameHub {
 public:
  // At most `max_viewers` at once, each with a queue of `queue_capacity` messages.
  FrameHub(int max_viewers, int queue_capacity);

  // A new viewer's id (> 0), or nullopt when max_viewers are watching.
  std::optional<int64_t> Join();
  // The viewer is gone: its queue is freed. Unknown ids are ignored.
  void Leave(int64_t viewer);
  // Queues `message` for every viewer (dropping each full queue's oldest).
  void Publish(const std::string& message);
  // Queues `message` for one viewer only (e.g. a refusal).
  void SendTo(int64_t viewer, const std::string& message);
  // The viewer's next message, waiting up to `timeout`; nullopt on timeout, or when the viewer
  // is unknown or the hub is closed.
  std::optional<std::string> Take(int64_t viewer, std::chrono::milliseconds timeout);
  // Wakes every waiting Take; later Takes return nullopt at once.
  void Close();

  int viewers() const;
  bool has_viewer(int64_t viewer) const;
  bool closed() const;
  // Messages dropped from full queues since the start, over all viewers.
  int64_t dropped() const;
  int64_t published() const;

 private:
  struct Viewer {
    std::deque<std::string> queue;
  };
  void Push(Viewer* viewer, const std::string& message);

  const int max_viewers_;
  const size_t capacity_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::map<int64_t, std::shared_ptr<Viewer>> viewers_;
  int64_t next_id_ = 1;
  int64_t dropped_ = 0;
  int64_t published_ = 0;
  bool closed_ = false;
};

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_FRAME_HUB_H_
