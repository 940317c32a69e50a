// Child processes and learner metrics for the multi-process benchmarks (soak, scale): this
// binary run as `juggle learner` or `juggle worker`, its RSS and CPU time, a learner's unroll
// accounts scraped from /metrics, and free loopback ports.
#ifndef JUGGLE_BENCH_BENCH_PROCESSES_H_
#define JUGGLE_BENCH_BENCH_PROCESSES_H_

#include <sys/types.h>

#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "envs/registry.h"

namespace juggle {

// This same binary (/proc/self/exe) run with `args`, stdout and stderr appended to `log`.
class SelfProcess {
 public:
  SelfProcess(const std::vector<std::string>& args, const std::string& log);
  ~SelfProcess() { Stop(9); }  // SIGKILL
  SelfProcess(const SelfProcess&) = delete;
  SelfProcess& operator=(const SelfProcess&) = delete;
  // Sends `sig` and reaps the process (up to 60 s); returns its exit code (-1: signalled).
  int Stop(int sig);
  double RssMb() const;        // VmRSS in MiB, or -1
  double CpuSeconds() const;   // user + system time so far, or -1

 private:
  pid_t pid_ = -1;
};

// The learner's unroll accounts and progress, from one /metrics scrape.
struct Accounts {
  bool ok = false;
  double accepted = 0, trained = 0, dropped = 0, held = 0, partial = 0, queued_chunks = 0;
  double iterations = 0, version = 0, workers = 0, samples = 0;
  double lag_sum = 0, lag_count = 0;  // juggle_policy_lag_versions histogram
  double broadcast_sum = 0, broadcast_count = 0;  // juggle_policy_broadcast_seconds histogram
  std::map<std::string, double> dropped_by_reason;
  double unaccounted() const { return accepted - trained - dropped - held - partial; }
};
Accounts Scrape(int metrics_port);

// The run config at `path`; INVALID_ARGUMENT naming `bench` unless it is asynchronous (the
// process benches need a learner that trains on whatever arrives).
absl::StatusOr<LoadedConfig> LoadAsynchronousConfig(const std::string& path,
                                                    const std::string& bench);

// A free TCP port on 127.0.0.1 (0 if none).
int FreeLoopbackPort();

}  // namespace juggle

#endif  // JUGGLE_BENCH_BENCH_PROCESSES_H_
