// `juggle bench dashboard`: does watching the dashboard slow training? Local training (the
// learner and one worker in this process, as `juggle train`) alternates phases without and
// with a client that polls everything the page fetches (/api/status, the incremental
// /api/history, /api/evals) plus /metrics, `poll_hz` times a second (the page refreshes every
// 3 s; the default 1 Hz is three open pages and a Prometheus). Prints samples/s off and on,
// their ratio, the time per request, and (training stopped) the CPU one full refresh costs.
// The last line is key=value pairs.
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "bench/benchmarks.h"
#include "common/http_server.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "learner/dashboard_json.h"
#include "learner/dashboard_state.h"
#include "learner/learner_server.h"
#include "learner/testing/recording_observer.h"
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

// User + system CPU time of this process.
double ProcessCpuSeconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
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
  // Each iteration's samples and wall time, credited to the phase it ended in: finer than
  // counting samples per phase (an iteration is thousands of samples).
  std::atomic<int> phase{-1};
  std::mutex mu;
  std::vector<double> phase_samples(2, 0), phase_seconds(2, 0);
  IterationCallback credit([&](const runlog::IterationRecord& r) {
    const int p = phase.load();
    if (p < 0) return;
    std::lock_guard<std::mutex> lock(mu);
    phase_samples[p % 2] += static_cast<double>(r.iteration_samples());
    phase_seconds[p % 2] += r.iteration_s();
  });
  options.observers.push_back(&credit);
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
  // Warm-up: until training runs.
  const auto warm_until = Clock::now() + std::chrono::seconds(120);
  while (learner.metrics().Get("juggle_iterations_total") < 2 && Clock::now() < warm_until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }

  // Alternating phases: off, on, off, on, ...
  std::vector<double> request_ms;
  size_t bytes = 0;
  int refreshes = 0;
  int64_t since = 0, stride = 0;
  for (int p = 0; p < 2 * o.repeats; ++p) {
    const bool polling = p % 2 == 1;
    double s0, t0_s;
    {
      std::lock_guard<std::mutex> lock(mu);
      s0 = phase_samples[p % 2];
      t0_s = phase_seconds[p % 2];
    }
    phase = p;
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
    std::lock_guard<std::mutex> lock(mu);
    const double ds = phase_samples[p % 2] - s0, dt = phase_seconds[p % 2] - t0_s;
    std::printf("phase %d (%s): %.0f samples/s\n", p, polling ? "polled" : "quiet",
                dt > 0 ? ds / dt : 0);
    std::fflush(stdout);
  }
  phase = -1;
  stop = true;
  trainer.join();
  worker_stop = true;
  worker.join();
  // The CPU one refresh costs (server and this client together), measured with nothing else
  // running in the process: back-to-back refreshes, each a fresh page load (full history).
  const int kRefreshes = 200;
  const double cpu0 = ProcessCpuSeconds();
  for (int i = 0; i < kRefreshes; ++i) {
    int64_t fresh_since = 0, fresh_stride = 0;
    std::vector<double> unused;
    PollOnce(learner.metrics_port(), &fresh_since, &fresh_stride, &unused);
  }
  const double cpu_ms_per_refresh = 1000 * (ProcessCpuSeconds() - cpu0) / kRefreshes;
  learner.Shutdown();

  // The largest history the page can load: DashboardState's full capacity.
  DashboardState full(DashboardRunInfo{}, DashboardState::kDefaultCapacity);
  runlog::IterationRecord report;
  (*report.mutable_outcomes())["ball_lost"] = 80;
  (*report.mutable_outcomes())["time_limit"] = 3;
  const WalkEventTotals no_events;
  const std::vector<double> no_counts;
  for (int i = 1; i <= DashboardState::kDefaultCapacity; ++i) {
    report.set_iteration(i);
    full.OnIteration({report, no_events, no_counts}).IgnoreError();
  }
  const auto h0 = Clock::now();
  const std::string full_history = HistoryJson(full.HistorySince(0, 0));
  const double full_history_ms = 1000 * Seconds(Clock::now() - h0);
  std::system(absl::StrCat("rm -rf ", options.run_dir).c_str());

  std::sort(request_ms.begin(), request_ms.end());
  const double median_ms = request_ms.empty() ? 0 : request_ms[request_ms.size() / 2];
  const double p99_ms = request_ms.empty() ? 0 : request_ms[request_ms.size() * 99 / 100];
  const double off_rate = phase_seconds[0] > 0 ? phase_samples[0] / phase_seconds[0] : 0;
  const double on_rate = phase_seconds[1] > 0 ? phase_samples[1] / phase_seconds[1] : 0;
  std::printf("training %.0f samples/s unwatched, %.0f samples/s polled at %.1f Hz "
              "(%d refreshes of 4 requests, %.0f kB each; request median %.2f ms, p99 %.2f ms)\n",
              off_rate, on_rate, o.poll_hz, refreshes, refreshes ? bytes / 1024.0 / refreshes : 0,
              median_ms, p99_ms);
  std::printf("a first page load at full history (%d points): %.0f kB of /api/history built in "
              "%.1f ms\n", DashboardState::kDefaultCapacity, full_history.size() / 1024.0,
              full_history_ms);
  // The page refreshes every 3 s: its share of one core.
  std::printf("one full refresh costs %.2f ms of CPU (server + client): %.3f %% of a core at the "
              "page's 3 s refresh\n", cpu_ms_per_refresh, 100 * cpu_ms_per_refresh / 3000);
  std::printf("off_samples_per_s=%.1f on_samples_per_s=%.1f on_over_off=%.4f request_median_ms=%.3f "
              "request_p99_ms=%.3f refresh_kb=%.1f cpu_ms_per_refresh=%.3f full_history_ms=%.2f\n",
              off_rate, on_rate, off_rate > 0 ? on_rate / off_rate : 0, median_ms, p99_ms,
              refreshes ? bytes / 1024.0 / refreshes : 0, cpu_ms_per_refresh, full_history_ms);
  return absl::OkStatus();
}

}  // namespace juggle
