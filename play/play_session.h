// The live simulation behind `juggle play` (docs/play.md): one thread steps a PlayWorld at the
// speed of the clock (or at the speed the controller achieves, when it is slower), applies the
// page's commands between steps and publishes a frame — the drawn bodies' world transforms and
// the world's status — to every viewer through a FrameHub, at most `max_frame_rate` per wall
// second. An episode that ends shows its end for `restart_pause_s` and restarts from the next
// start. Thread-safe: Submit and the accessors from any thread.
#ifndef JUGGLE_PLAY_PLAY_SESSION_H_
#define JUGGLE_PLAY_PLAY_SESSION_H_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/statusor.h"
#include "export/replay.h"
#include "nlohmann/json.hpp"
#include "play/frame_hub.h"
#include "play/play_commands.h"
#include "play/play_world.h"

namespace juggle::play {

struct SessionOptions {
  double speed = 1.0;            // simulated seconds per wall second asked for
  double restart_pause_s = 1.5;  // wall seconds an ended episode stays on screen
  int max_frame_rate = 60;       // frames per wall second at most
  uint64_t first_seed = 0;       // the first episode's start (then +1 per restart)
  bool start_paused = false;
  // Steps as fast as the world allows, without pacing (benchmarks: bench/play_bench.cc).
  bool unpaced = false;
};

// What the simulation thread spent, for the stream's share of it (CPU time of the thread).
struct SessionTimes {
  int64_t steps = 0;
  int64_t frames = 0;
  double step_seconds = 0;    // CPU s in PlayWorld::Step (the controller and the physics)
  double frame_seconds = 0;   // CPU s building and publishing frames
  double sim_seconds = 0;     // simulated time stepped
  double wall_seconds = 0;    // since Start
  // frame_seconds / step_seconds: what streaming costs the simulation.
  double stream_share() const { return step_seconds > 0 ? frame_seconds / step_seconds : 0; }
};

class PlaySession {
 public:
  PlaySession(std::unique_ptr<PlayWorld> world, FrameHub* hub, SessionOptions options);
  ~PlaySession();

  void Start();
  // Ends the thread (waits for the step in progress). Idempotent.
  void Stop();

  // Applies `command` between two steps, waiting up to 5 s for it. The text for the page
  // ("poked the ball with 0.50 N·s", ...), or the world's refusal (INVALID_ARGUMENT,
  // FAILED_PRECONDITION) or DEADLINE_EXCEEDED. Claim and release belong to the server.
  absl::StatusOr<std::string> Submit(const PlayCommand& command);

  // The page's scene: {"family", "control_dt", "bodies", "follow", "geoms", "options"}.
  nlohmann::json Scene() const { return scene_; }
  // The latest frame's JSON (for a viewer that just joined), or "" before the first.
  std::string LatestFrame() const;
  SessionTimes times() const;
  // Simulated seconds per wall second over the last ~2 s of stepping (pauses and restarts
  // start a new window; until it spans 0.5 s, the last window's value).
  double achieved_speed() const;
  int64_t episodes() const { return episodes_.load(); }

 private:
  struct Pending {
    PlayCommand command;
    std::promise<absl::StatusOr<std::string>> done;
  };
  void Run();
  absl::StatusOr<std::string> Apply(const PlayCommand& command);
  // Publishes the state as a frame; `status_changed`: rebuild the status now.
  void PublishFrame(bool status_changed);
  std::string StatusJson();
  void Restart(uint64_t seed);
  // Starts a new window for achieved_speed (keeping the last one's value until it fills).
  void ForgetSpeed();

  std::unique_ptr<PlayWorld> world_;
  FrameHub* hub_;
  SessionOptions options_;
  ReplayScene scene_bodies_;
  nlohmann::json scene_;

  std::thread thread_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mu_;  // pending_, latest_frame_, times_, speed samples
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Pending>> pending_;
  std::string latest_frame_;
  SessionTimes times_;
  std::deque<std::pair<double, double>> speed_samples_;  // (wall s, sim s)
  double achieved_ = 0;  // the last full window's speed

  // Simulation-thread state.
  double speed_ = 1;
  bool paused_ = false;
  bool ended_ = false;
  double ended_at_ = 0;
  uint64_t seed_ = 0;
  double sim_time_ = 0;       // of the episode
  double total_sim_ = 0;      // over every episode
  std::string message_;       // the last command's effect, shown on the page
  std::string status_json_;   // the status object of the frames, rebuilt every 0.2 s
  double status_built_ = 0;
  std::string frame_buffer_;
  std::atomic<int64_t> episodes_{0};
};

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_PLAY_SESSION_H_
