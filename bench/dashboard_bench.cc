// `juggle bench dashboard`: does watching the dashboard slow training? Local training (the
// learner and one worker in this process, as `juggle train`) alternates phases without and
// with a client that polls everything the page fetches (/api/status, the incremental
// /api/history, /api/evals) plus /metrics, `poll_hz` times a second (the page refreshes every
// 3 s; the default 1 Hz is three open pages and a Prometheus). Prints samples/s off and on,
// their ratio, and the server's time per request. The last line is key=value pairs.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "bench/benchmarks.h"
#include "common/http_server.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "learner/learner_server.h"
#include "nlohmann/json.hpp"
#include "worker/worker_client.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// One page refresh's requests; returns the bytes received. `since`/`stride` follow the
// history as the page does.
size_t PollOnce(int port, int64_t* since, int64_t* stride, std::vector<double>* request_ms) {
  size_t bytes = 0;
  const std::string paths[] = {
      "/api/status", absl::StrCat("/api/history?since=", *since, "&stride=", *stride),
      "/api/evals", "/metrics"};
  for (const std::string& path : paths) {
    const auto t = Clock::now();
    absl::StatusOr<std::string> body = HttpGet(port, path);
    request_ms->push_back(1000 * Seconds(Clock::now() - t));
    if (!body.ok()) continue;
    bytes += body->size();
    if (path.rfind("/api/history", 0) == 0) {
      const nlohmann::json h = nlohmann::json::parse(*body, nullptr, false);
      if (!h.is_discarded()) {
        *since = h.value("last", int64_t{0});
        *stride = h.value("stride", int64_t{1});
      }
    }
  }
  return bytes;
}

}  // namespace

absl::Status RunDashboardBench(const DashboardBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  const config::RunConfig& run = config->run;
  LearnerOptions options;
  options.config = *config;
  options.run_dir = MakeTempDir("juggle_bench_dashboard_");
  options.port = 0;
  options.metrics_port = LearnerOptions::kAnyFreePort;
  options.listen_all_interfaces = false;
  absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(std::move(options));
  if (!server.ok()) return server.status();
  LearnerServer& learner = **server;
  std::atomic<bool> stop{false}, worker_stop{false};
  std::thread worker([&] {
    WorkerOptions w;
    w.learner_address = absl::StrCat("127.0.0.1:", learner.port());
    w.num_envs = run.sampling().num_envs();
    w.num_threads = run.sampling().num_threads();
    w.requested_slot = 0;
    w.stop = &worker_stop;
    w.verbose = false;
    RunWorker(w).IgnoreError();
  });
  std::thread trainer([&] { learner.Train(&stop).IgnoreError(); });
  auto samples = [&] { return learner.metrics().Get("juggle_samples_total"); };
  // Warm-up: until training runs.
  const auto warm_until = Clock::now() + std::chrono::seconds(120);
  while (learner.metrics().Get("juggle_iterations_total") < 2 && Clock::now() < warm_until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }

  // Alternating phases: off, on, off, on, ...
  double off_samples = 0, off_s = 0, on_samples = 0, on_s = 0;
  std::vector<double> request_ms;
  size_t bytes = 0;
  int refreshes = 0;
  int64_t since = 0, stride = 0;
  for (int phase = 0; phase < 2 * o.repeats; ++phase) {
    const bool polling = phase % 2 == 1;
    const double s0 = samples();
    const auto t0 = Clock::now();
    const auto end = t0 + std::chrono::milliseconds(static_cast<int>(1000 * o.phase_seconds));
    auto next = t0;
    while (Clock::now() < end) {
      if (polling && Clock::now() >= next) {
        bytes += PollOnce(learner.metrics_port(), &since, &stride, &request_ms);
        ++refreshes;
        next += std::chrono::milliseconds(static_cast<int>(1000 / o.poll_hz));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const double ds = samples() - s0, dt = Seconds(Clock::now() - t0);
    (polling ? on_samples : off_samples) += ds;
    (polling ? on_s : off_s) += dt;
    std::printf("phase %d (%s): %.0f samples/s\n", phase, polling ? "polled" : "quiet", ds / dt);
    std::fflush(stdout);
  }
  stop = true;
  trainer.join();
  worker_stop = true;
  worker.join();
  learner.Shutdown();
  std::system(absl::StrCat("rm -rf ", options.run_dir).c_str());

  std::sort(request_ms.begin(), request_ms.end());
  const double median_ms = request_ms.empty() ? 0 : request_ms[request_ms.size() / 2];
  const double p99_ms = request_ms.empty() ? 0 : request_ms[request_ms.size() * 99 / 100];
  const double off_rate = off_s > 0 ? off_samples / off_s : 0;
  const double on_rate = on_s > 0 ? on_samples / on_s : 0;
  std::printf("training %.0f samples/s unwatched, %.0f samples/s polled at %.1f Hz "
              "(%d refreshes of 4 requests, %.0f kB each; request median %.2f ms, p99 %.2f ms)\n",
              off_rate, on_rate, o.poll_hz, refreshes, refreshes ? bytes / 1024.0 / refreshes : 0,
              median_ms, p99_ms);
  std::printf("off_samples_per_s=%.1f on_samples_per_s=%.1f on_over_off=%.4f request_median_ms=%.3f "
              "request_p99_ms=%.3f refresh_kb=%.1f\n",
              off_rate, on_rate, off_rate > 0 ? on_rate / off_rate : 0, median_ms, p99_ms,
              refreshes ? bytes / 1024.0 / refreshes : 0);
  return absl::OkStatus();
}

}  // namespace juggle
