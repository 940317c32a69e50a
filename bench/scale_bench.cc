// `juggle bench scale`: one learner process (asynchronous) and 8, 16, 32, 64 real worker
// processes (`juggle worker`, 1 env and 1 thread each) on loopback. Per count, after a warm-up:
// samples/s accepted and trained, the learner's CPU (cores) and RSS, the mean policy lag of the
// trained unrolls, the mean time a new policy version takes to reach every worker
// (juggle_policy_broadcast_seconds), and what was dropped as stale — where one learner saturates and what
// happens then. The last line is key=value pairs.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "bench/bench_processes.h"
#include "bench/benchmarks.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

void Sleep(double seconds) {
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000)));
}

}  // namespace

absl::Status RunScaleBench(const ScaleBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadAsynchronousConfig(o.config, "the scale bench");
  if (!config.ok()) return config.status();
  const int T = config->run.ppo().unroll_length();
  std::vector<int> counts;
  for (absl::string_view c : absl::StrSplit(o.workers, ',')) {
    int n = 0;
    if (!absl::SimpleAtoi(c, &n) || n < 1 || n > 1024) {
      return absl::InvalidArgumentError(absl::StrCat("--workers: '", c, "' is not a count in [1, 1024]"));
    }
    counts.push_back(n);
  }
  const std::string dir = MakeTempDir("juggle_scale_");
  std::printf("scale: %s, %.0f s warm-up + %.0f s measured per worker count; logs in %s\n",
              o.config.c_str(), o.warmup_s, o.seconds, dir.c_str());
  std::printf("%8s %12s %12s %10s %9s %9s %13s %12s %9s\n", "workers", "accepted/s", "trained/s",
              "learner", "rss MiB", "lag", "broadcast ms", "stale/s", "live");
  std::string summary;
  for (int n : counts) {
    const std::string run = absl::StrCat(dir, "/w", n);
    std::filesystem::create_directories(run);
    const int port = FreeLoopbackPort(), metrics_port = FreeLoopbackPort();
    SelfProcess learner({"learner", "--config=" + o.config, "--port=" + std::to_string(port),
                         "--metrics_port=" + std::to_string(metrics_port), "--run_dir=" + run + "/run"},
                        run + "/learner.log");
    for (int i = 0; i < 300 && !Scrape(metrics_port).ok; ++i) Sleep(0.1);
    std::vector<std::unique_ptr<SelfProcess>> workers;
    for (int w = 0; w < n; ++w) {
      workers.push_back(std::make_unique<SelfProcess>(
          std::vector<std::string>{"worker", "--learner=127.0.0.1:" + std::to_string(port),
                                   "--envs=1", "--threads=1", "--give_up_after=60"},
          absl::StrCat(run, "/worker", w, ".log")));
    }
    Sleep(o.warmup_s);
    const Accounts a0 = Scrape(metrics_port);
    const double cpu0 = learner.CpuSeconds();
    const auto t0 = Clock::now();
    Sleep(o.seconds);
    const Accounts a1 = Scrape(metrics_port);
    const double cpu1 = learner.CpuSeconds();
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    const double rss = learner.RssMb();
    for (auto& w : workers) w->Stop(15);  // SIGTERM
    learner.Stop(15);
    if (!a0.ok || !a1.ok) return absl::UnavailableError(absl::StrCat("the learner of ", n, " workers did not answer /metrics (", run, ")"));
    const double accepted = (a1.accepted - a0.accepted) * T / dt;
    const double trained = (a1.samples - a0.samples) / dt;
    const double cores = (cpu1 - cpu0) / dt;
    const double lag_n = a1.lag_count - a0.lag_count;
    const double lag = lag_n > 0 ? (a1.lag_sum - a0.lag_sum) / lag_n : 0;
    const double broadcasts = a1.broadcast_count - a0.broadcast_count;
    const double broadcast_ms =
        broadcasts > 0 ? 1000 * (a1.broadcast_sum - a0.broadcast_sum) / broadcasts : 0;
    const double stale = ((a1.dropped_by_reason.count("stale") ? a1.dropped_by_reason.at("stale") : 0) -
                          (a0.dropped_by_reason.count("stale") ? a0.dropped_by_reason.at("stale") : 0)) * T / dt;
    std::printf("%8d %12.0f %12.0f %9.2fc %9.0f %9.2f %13.1f %12.0f %9.0f\n", n, accepted, trained,
                cores, rss, lag, broadcast_ms, stale, a1.workers);
    std::fflush(stdout);
    absl::StrAppend(&summary, " accepted_", n, "=", static_cast<int64_t>(accepted), " trained_", n,
                    "=", static_cast<int64_t>(trained), " learner_cores_", n, "=", cores,
                    " rss_mb_", n, "=", static_cast<int64_t>(rss), " lag_", n, "=", lag, " broadcast_ms_", n, "=", broadcast_ms);
  }
  std::printf("scale:%s\n", summary.c_str());
  return absl::OkStatus();
}

}  // namespace juggle
