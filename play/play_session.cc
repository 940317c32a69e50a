#include "play/play_session.h"

#include <time.h>

#include <chrono>
#include <cmath>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "export/trajectory_model.h"

namespace juggle::play {
namespace {

using Clock = std::chrono::steady_clock;

// Wall seconds between frames while paused or showing an ended episode.
constexpr double kStillFrameInterval = 0.04;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// CPU seconds this thread has run: what stepping and streaming cost, whatever else shares the
// cores (wall time would also count the waits for a core).
double ThreadCpuSeconds() {
  timespec t;
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Fixed-point integer of v in units of 1e-4 (positions in 0.1 mm, quaternion components).
int64_t Fixed(double v) { return std::isfinite(v) ? std::llround(v * 1e4) : 0; }

}  // namespace

PlaySession::PlaySession(std::unique_ptr<PlayWorld> world, FrameHub* hub, SessionOptions options)
    : world_(std::move(world)),
      hub_(hub),
      options_(options),
      scene_bodies_(BuildReplayScene(world_->model())),
      speed_(options.speed),
      paused_(options.start_paused),
      seed_(options.first_seed) {
  scene_ = {{"family", world_->family()},
            {"control_dt", world_->control_dt()},
            {"scale", 10000},
            {"bodies", scene_bodies_.body_names},
            {"follow", scene_bodies_.follow},
            {"geoms", nlohmann::json::parse(ReplayGeomsJson(scene_bodies_.geoms))},
            {"options", world_->Options()}};
  const std::vector<int> balls = BallBodies(world_->model());
  if (!balls.empty()) scene_["ball_mass"] = world_->model()->body_subtreemass[balls.front()];
  world_->Restart(seed_);
}

PlaySession::~PlaySession() { Stop(); }

void PlaySession::Start() {
  if (thread_.joinable()) return;
  thread_ = std::thread([this] { Run(); });
}

void PlaySession::Stop() {
  stop_ = true;
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  // Commands still waiting get an answer.
  std::lock_guard<std::mutex> lock(mu_);
  for (auto& p : pending_) p->done.set_value(absl::UnavailableError("the session stopped"));
  pending_.clear();
}

absl::StatusOr<std::string> PlaySession::Submit(const PlayCommand& command) {
  auto pending = std::make_shared<Pending>();
  pending->command = command;
  std::future<absl::StatusOr<std::string>> done = pending->done.get_future();
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (stop_) return absl::UnavailableError("the session stopped");
    pending_.push_back(pending);
  }
  wake_.notify_all();
  if (done.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
    return absl::DeadlineExceededError("the simulation did not take the command within 5 s");
  }
  return done.get();
}

std::string PlaySession::LatestFrame() const {
  std::lock_guard<std::mutex> lock(mu_);
  return latest_frame_;
}

SessionTimes PlaySession::times() const {
  std::lock_guard<std::mutex> lock(mu_);
  return times_;
}

double PlaySession::achieved_speed() const {
  std::lock_guard<std::mutex> lock(mu_);
  if (speed_samples_.size() < 2) return 0;
  const auto& [w0, s0] = speed_samples_.front();
  const auto& [w1, s1] = speed_samples_.back();
  return w1 - w0 >= 0.5 ? (s1 - s0) / (w1 - w0) : achieved_;
}

void PlaySession::ForgetSpeed() {
  std::lock_guard<std::mutex> lock(mu_);
  if (speed_samples_.size() >= 2) {
    const auto& [w0, s0] = speed_samples_.front();
    const auto& [w1, s1] = speed_samples_.back();
    if (w1 - w0 >= 0.5) achieved_ = (s1 - s0) / (w1 - w0);
  }
  speed_samples_.clear();
}

void PlaySession::Restart(uint64_t seed) {
  seed_ = seed;
  world_->Restart(seed);
  ForgetSpeed();
  ended_ = false;
  sim_time_ = 0;
  episodes_++;
}

absl::StatusOr<std::string> PlaySession::Apply(const PlayCommand& c) {
  switch (c.kind) {
    case CommandKind::kPause:
      paused_ = true;
      ForgetSpeed();
      return std::string("paused");
    case CommandKind::kResume:
      paused_ = false;
      return std::string("running");
    case CommandKind::kSpeed:
      speed_ = c.factor;
      return absl::StrFormat("speed %gx", c.factor);
    case CommandKind::kRestart:
      Restart(c.has_seed ? c.seed : seed_ + 1);
      return absl::StrCat("new start: seed ", seed_);
    case CommandKind::kPoke: {
      if (ended_) return absl::FailedPreconditionError("the episode is over: wait for the restart");
      if (absl::Status s = world_->Poke(c.impulse); !s.ok()) return s;
      const double n = std::sqrt(c.impulse[0] * c.impulse[0] + c.impulse[1] * c.impulse[1] +
                                 c.impulse[2] * c.impulse[2]);
      return absl::StrFormat("poked the ball: %.2f N·s (%.2f, %.2f, %.2f)", n, c.impulse[0],
                             c.impulse[1], c.impulse[2]);
    }
    case CommandKind::kSkill:
      if (absl::Status s = world_->Choose(c.name); !s.ok()) return s;
      return c.name == "walk" ? std::string("the adaptive walk chooses the skills")
                              : absl::StrCat("next skill: ", c.name);
    case CommandKind::kPattern:
      if (absl::Status s = world_->Choose(c.name); !s.ok()) return s;
      return absl::StrCat("next pattern: ", c.name);
    case CommandKind::kWind:
      if (absl::Status s = world_->SetWind(c.newtons); !s.ok()) return s;
      return absl::StrFormat("wind %.2f N", c.newtons);
    case CommandKind::kStep: {
      if (!paused_) return absl::FailedPreconditionError("step: pause first");
      if (ended_) return absl::FailedPreconditionError("the episode is over: restart");
      for (int i = 0; i < c.steps && !ended_; ++i) {
        ended_ = !world_->Step();
        sim_time_ += world_->control_dt();
        total_sim_ += world_->control_dt();
        if (ended_) ended_at_ = 0;  // restarts as soon as it is resumed
      }
      return absl::StrFormat("stepped to %.2f s", sim_time_);
    }
    case CommandKind::kClaim:
    case CommandKind::kRelease:
      break;
  }
  return absl::InvalidArgumentError(
      absl::StrCat(CommandName(c.kind), " is not a simulation command"));
}

std::string PlaySession::StatusJson() {
  nlohmann::json status = {{"episode", episodes_.load()},
                           {"paused", paused_},
                           {"speed", speed_},
                           {"achieved", achieved_speed()},
                           {"message", message_}};
  world_->AppendStatus(&status);
  return status.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void PlaySession::PublishFrame(bool status_changed) {
  // Written by hand (not through a JSON tree): a frame is built after every control step, and
  // its cost is the stream's share of the simulation (docs/play.md, "What streaming costs").
  // The status object is rebuilt at most every 0.2 s of wall time, or when it changed.
  const double now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  if (status_changed || status_json_.empty() || now - status_built_ >= 0.2) {
    status_json_ = StatusJson();
    status_built_ = now;
  }
  const mjData* d = world_->data();
  std::string& text = frame_buffer_;
  text.clear();
  text.append("data: {\"type\":\"frame\",\"t\":");
  absl::StrAppend(&text, absl::StrFormat("%.4f", sim_time_), ",\"x\":[");
  char number[absl::numbers_internal::kFastToBufferSize + 1];
  auto append_fixed = [&text, &number](double v, bool comma) {
    char* start = number;
    if (comma) *start++ = ',';
    char* end = absl::numbers_internal::FastIntToBuffer(Fixed(v), start);
    text.append(number, end - number);
  };
  bool first = true;
  for (int b : scene_bodies_.body_ids) {
    for (int k = 0; k < 3; ++k, first = false) append_fixed(d->xpos[3 * b + k], !first);
  }
  text.append("],\"q\":[");
  first = true;
  for (int b : scene_bodies_.body_ids) {
    for (int k = 0; k < 4; ++k, first = false) append_fixed(d->xquat[4 * b + k], !first);
  }
  text.append("],\"status\":");
  text.append(status_json_);
  text.append("}\n\n");
  {
    std::lock_guard<std::mutex> lock(mu_);
    latest_frame_ = text;
  }
  hub_->Publish(text);
}

void PlaySession::Run() {
  const Clock::time_point start = Clock::now();
  auto now_s = [start] { return Seconds(start, Clock::now()); };
  double anchor_wall = 0, anchor_sim = 0, last_frame = -1;
  const double frame_interval = 1.0 / std::max(1, options_.max_frame_rate);
  // Without viewers a frame is built only now and then (for the next viewer's first frame).
  auto frame_due = [&](double interval) {
    return now_s() - last_frame >= (hub_->viewers() > 0 ? interval : 0.25);
  };
  PublishFrame(true);
  while (!stop_) {
    // Commands first, between two steps.
    std::deque<std::shared_ptr<Pending>> work;
    {
      std::lock_guard<std::mutex> lock(mu_);
      work.swap(pending_);
    }
    for (auto& p : work) {
      absl::StatusOr<std::string> r = Apply(p->command);
      message_ = r.ok() ? *r : std::string(r.status().message());
      p->done.set_value(std::move(r));
    }
    if (!work.empty()) {
      anchor_wall = now_s();
      anchor_sim = total_sim_;
      PublishFrame(true);
      last_frame = now_s();
    }
    if (paused_ || ended_) {
      bool restarted = false;
      if (ended_ && now_s() - ended_at_ >= options_.restart_pause_s) {
        Restart(seed_ + 1);
        message_ = absl::StrCat("new start: seed ", seed_);
        restarted = true;
      }
      // Frames go on while nothing moves (the page's clock and messages stay live).
      if (restarted || frame_due(kStillFrameInterval)) {
        PublishFrame(restarted);
        last_frame = now_s();
      }
      std::unique_lock<std::mutex> lock(mu_);
      wake_.wait_for(lock, std::chrono::milliseconds(20),
                     [this] { return stop_ || !pending_.empty(); });
      anchor_wall = now_s();
      anchor_sim = total_sim_;
      continue;
    }
    const double t0 = ThreadCpuSeconds();
    const bool running = world_->Step();
    const double step_seconds = ThreadCpuSeconds() - t0;
    sim_time_ += world_->control_dt();
    total_sim_ += world_->control_dt();
    if (!running) {
      ended_ = true;
      ended_at_ = now_s();
    }
    double frame_seconds = 0;
    if (!running || frame_due(frame_interval)) {
      const double f0 = ThreadCpuSeconds();
      PublishFrame(!running);
      frame_seconds = ThreadCpuSeconds() - f0;
      last_frame = now_s();
    }
    const double wall = now_s();
    {
      std::lock_guard<std::mutex> lock(mu_);
      times_.steps++;
      times_.step_seconds += step_seconds;
      if (frame_seconds > 0) {
        times_.frames++;
        times_.frame_seconds += frame_seconds;
      }
      times_.sim_seconds = total_sim_;
      times_.wall_seconds = wall;
      speed_samples_.emplace_back(wall, total_sim_);
      while (speed_samples_.size() > 2 && wall - speed_samples_.front().first > 2.0) {
        speed_samples_.pop_front();
      }
    }
    // Pacing: simulated time runs at `speed_` against the wall clock; a controller slower than
    // that runs at its own speed (the anchor moves up, no debt piles up).
    const double target = anchor_wall + (total_sim_ - anchor_sim) / speed_;
    if (options_.unpaced) continue;
    if (target > wall) {
      std::unique_lock<std::mutex> lock(mu_);
      wake_.wait_for(lock, std::chrono::duration<double>(target - wall),
                     [this] { return stop_.load() || !pending_.empty(); });
    } else if (wall - target > world_->control_dt()) {
      // Behind (a slow step): run on from here, without racing to make the time up.
      anchor_wall = wall;
      anchor_sim = total_sim_;
    }
  }
}

}  // namespace juggle::play
