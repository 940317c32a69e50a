// Helpers of the network-fault tests: wall time since a moment, the learner's unroll accounts
// from /metrics, the workers' side of them from their logs, a process's RSS, and a thread's
// network namespace.
#ifndef JUGGLE_TESTS_NETFAULTS_NETFAULTS_UTIL_H_
#define JUGGLE_TESTS_NETFAULTS_NETFAULTS_UTIL_H_

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "common/http_server.h"

namespace juggle::netfaults {

using Clock = std::chrono::steady_clock;

// Seconds of wall time since `t`.
inline double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The learner's unroll accounts (docs/reliability.md, "Limits"): accepted = trained + dropped
// + held + partial + what waits in the ingestion queue.
struct Accounts {
  bool ok = false;
  double accepted = 0, trained = 0, dropped = 0, held = 0, partial = 0, queued_chunks = 0;
  double version = 0, workers = 0, samples = 0, stragglers = 0, timeouts = 0;
  std::map<std::string, double> dropped_by_reason;
  double unaccounted() const { return accepted - trained - dropped - held - partial; }
};

inline Accounts ScrapeAccounts(int metrics_port) {
  static const std::map<std::string, double Accounts::*> kFields = {
      {"juggle_unrolls_accepted_total", &Accounts::accepted},
      {"juggle_unrolls_trained_total", &Accounts::trained},
      {"juggle_unrolls_held", &Accounts::held},
      {"juggle_unrolls_partial", &Accounts::partial},
      {"juggle_ingest_queue_chunks", &Accounts::queued_chunks},
      {"juggle_policy_version", &Accounts::version},
      {"juggle_workers_connected", &Accounts::workers},
      {"juggle_samples_total", &Accounts::samples},
      {"juggle_sync_round_stragglers_total", &Accounts::stragglers},
      {"juggle_worker_timeouts_total", &Accounts::timeouts},
  };
  Accounts a;
  absl::StatusOr<std::string> body = HttpGet(metrics_port, "/metrics");
  if (!body.ok()) return a;
  a.ok = true;
  std::istringstream in(*body);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::string name = line.substr(0, line.find_first_of(" {"));
    const double value = std::stod(line.substr(line.rfind(' ') + 1));
    if (auto f = kFields.find(name); f != kFields.end()) {
      a.*(f->second) = value;
    } else if (name == "juggle_unrolls_dropped_total") {
      const size_t r = line.find("reason=\"");
      a.dropped_by_reason[r == std::string::npos ? "?" : line.substr(r + 8, line.find('"', r + 8) - r - 8)] += value;
      a.dropped += value;
    }
  }
  return a;
}

// What a worker's log says the learner acknowledged (worker/worker_client.cc prints it as it
// exits); -1 when the line is missing.
struct Acks {
  long unrolls = -1, chunks = -1, sessions = -1;
};
inline Acks ReadAcks(const std::string& log_path) {
  std::ifstream in(log_path);
  std::string line;
  Acks acks;
  static const std::regex kLine(
      "the learner acknowledged ([0-9]+) unrolls in ([0-9]+) chunks over ([0-9]+) sessions");
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, kLine)) {
      acks.unrolls = std::stol(m[1]);
      acks.chunks = std::stol(m[2]);
      acks.sessions = std::stol(m[3]);
    }
  }
  return acks;
}

// VmRSS of `pid` in MiB, -1 if unknown.
inline double RssMb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      double kb = -1;
      in >> kb;
      return kb / 1024;
    }
  }
  return -1;
}

// Moves the calling thread into the named network namespace (/run/netns/NAME) for its
// lifetime, and back. Sockets made, threads started and processes forked by this thread
// meanwhile belong to that namespace. ok() is false if the move failed.
class InNamespace {
 public:
  explicit InNamespace(const std::string& name) {
    saved_ = ::open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC);
    const int fd = ::open(("/run/netns/" + name).c_str(), O_RDONLY | O_CLOEXEC);
    ok_ = saved_ >= 0 && fd >= 0 && ::setns(fd, CLONE_NEWNET) == 0;
    if (fd >= 0) ::close(fd);
  }
  ~InNamespace() {
    if (saved_ >= 0) {
      ::setns(saved_, CLONE_NEWNET);
      ::close(saved_);
    }
  }
  bool ok() const { return ok_; }

 private:
  int saved_ = -1;
  bool ok_ = false;
};

}  // namespace juggle::netfaults

#endif  // JUGGLE_TESTS_NETFAULTS_NETFAULTS_UTIL_H_
