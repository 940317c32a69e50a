// `juggle bench play`: what streaming the live page costs the simulation (docs/play.md, issue
// 46's "at most 5 %"). One PlaySession stepping a config's env with the zero action, unpaced,
// (the toss family: the two-arm runtime juggling 3 with its base controllers) alternates
// phases without a viewer and with one viewer draining the stream as a browser does; prints control steps per wall second in each, their ratio, and the session's own
// account (time building and publishing frames over time stepping). The last line is key=value
// pairs.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "absl/strings/str_format.h"
#include "bench/benchmarks.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "play/env_world.h"
#include "play/frame_hub.h"
#include "play/play_session.h"
#include "play/siteswap_world.h"

namespace juggle {

absl::Status RunPlayBench(const PlayBenchOptions& options) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(options.config);
  if (!config.ok()) return config.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return spec.status();
  // The world `juggle play` plays: the toss family's two-arm runtime (pattern 3), or the env
  // with the zero action.
  std::unique_ptr<play::PlayWorld> world;
  if ((*spec)->family() == "toss") {
    absl::StatusOr<std::unique_ptr<play::SiteswapWorld>> toss =
        play::SiteswapWorld::Create(*spec, "3", /*run_seed=*/1);
    if (!toss.ok()) return toss.status();
    world = *std::move(toss);
  } else {
    world = std::make_unique<play::EnvWorld>(
        *spec, std::make_unique<ZeroController>((*spec)->act_dim()), nullptr, /*run_seed=*/1000);
  }
  play::FrameHub hub(2, 8);
  play::SessionOptions session_options;
  session_options.unpaced = true;
  session_options.restart_pause_s = 0;
  session_options.max_frame_rate = options.frame_rate;
  play::PlaySession session(std::move(world), &hub, session_options);
  session.Start();
  std::printf("bench play: %s, zero action or toss base, unpaced, %d frames/s at most, %d phase pairs of "
              "%.1f s\n",
              options.config.c_str(), options.frame_rate, options.repeats,
              options.phase_seconds);
  double steps_quiet = 0, steps_watched = 0, seconds_quiet = 0, seconds_watched = 0;
  double frame_s = 0, step_s = 0;
  int64_t frames = 0, received = 0;
  for (int r = 0; r < options.repeats; ++r) {
    for (const bool watched : {false, true}) {
      std::atomic<bool> stop{false};
      std::atomic<int64_t> got{0};
      std::thread viewer;
      if (watched) {
        const int64_t id = *hub.Join();
        viewer = std::thread([&hub, &stop, &got, id] {
          while (!stop) {
            if (hub.Take(id, std::chrono::milliseconds(50)).has_value()) ++got;
          }
          hub.Leave(id);
        });
      }
      const play::SessionTimes t0 = session.times();
      const auto start = std::chrono::steady_clock::now();
      std::this_thread::sleep_for(std::chrono::duration<double>(options.phase_seconds));
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const play::SessionTimes t1 = session.times();
      stop = true;
      if (viewer.joinable()) viewer.join();
      const double steps = static_cast<double>(t1.steps - t0.steps);
      std::printf("  %-8s %8.0f steps/s  frames %6lld  frame time / step time %.4f\n",
                  watched ? "watched" : "quiet", steps / wall,
                  static_cast<long long>(t1.frames - t0.frames),
                  t1.step_seconds > t0.step_seconds
                      ? (t1.frame_seconds - t0.frame_seconds) / (t1.step_seconds - t0.step_seconds)
                      : 0.0);
      if (watched) {
        steps_watched += steps;
        seconds_watched += wall;
        frame_s += t1.frame_seconds - t0.frame_seconds;
        step_s += t1.step_seconds - t0.step_seconds;
        frames += t1.frames - t0.frames;
        received += got;
      } else {
        steps_quiet += steps;
        seconds_quiet += wall;
      }
    }
  }
  session.Stop();
  const double quiet_rate = steps_quiet / seconds_quiet, watched_rate = steps_watched / seconds_watched;
  std::printf("steps_per_s_quiet=%.0f steps_per_s_watched=%.0f watched_over_quiet=%.4f "
              "stream_share=%.4f frame_us=%.1f step_us=%.1f frames=%lld received=%lld\n",
              quiet_rate, watched_rate, watched_rate / quiet_rate,
              step_s > 0 ? frame_s / step_s : 0, frames > 0 ? 1e6 * frame_s / frames : 0,
              steps_watched > 0 ? 1e6 * step_s / steps_watched : 0,
              static_cast<long long>(frames), static_cast<long long>(received));
  return absl::OkStatus();
}

}  // namespace juggle
