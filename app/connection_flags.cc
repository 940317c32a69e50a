#include "app/connection_flags.h"

#include <cmath>
#include <string>

#include "app/command.h"

namespace juggle {
namespace {

// 0 (off) or a time in [0.5, 86400] s.
CLI::Validator KeepaliveTime() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        try {
          size_t used = 0;
          v = std::stod(text, &used);
          if (used != text.size()) return "must be a number of seconds";
        } catch (...) {
          return "must be a number of seconds";
        }
        if (v == 0 || (std::isfinite(v) && v >= 0.5 && v <= 86400)) return "";
        return "must be 0 (off) or in [0.5, 86400] seconds";
      },
      "0 or [0.5, 86400]");
}

void AddKeepalive(CLI::App* cmd, double* time_s, double* timeout_s, const char* who,
                  const char* peer) {
  cmd->add_option("--keepalive_time", *time_s,
                  std::string("seconds between ") + who + "'s keepalive pings on each " + peer +
                      " connection (0: off); a connection whose ping goes unanswered for "
                      "--keepalive_timeout is closed")
      ->check(KeepaliveTime())
      ->capture_default_str();
  cmd->add_option("--keepalive_timeout", *timeout_s,
                  "seconds a keepalive ping may go unanswered before the connection is closed")
      ->check(Between(0.5, 3600))
      ->capture_default_str();
}

}  // namespace

void AddWorkerConnectionFlags(CLI::App* cmd, WorkerConnectionSettings* s) {
  AddKeepalive(cmd, &s->keepalive_time_s, &s->keepalive_timeout_s, "the worker", "learner");
  cmd->add_option("--keepalive_permit_without_calls", s->permit_without_calls,
                  "ping even while no call is open (true/false)")
      ->capture_default_str();
  cmd->add_option("--max_reconnect_backoff", s->max_reconnect_backoff_s,
                  "longest wait in seconds between reconnect attempts while the learner is "
                  "unreachable (the wait doubles from 0.1 s)")
      ->check(Between(0.1, 3600))
      ->capture_default_str();
  cmd->add_option("--min_connect_timeout", s->min_connect_timeout_s,
                  "seconds one connection attempt may take before it is abandoned (gRPC: 20)")
      ->check(Between(0.1, 3600))
      ->capture_default_str();
}

void AddLearnerConnectionFlags(CLI::App* cmd, LearnerConnectionSettings* s) {
  AddKeepalive(cmd, &s->keepalive_time_s, &s->keepalive_timeout_s, "the learner", "worker");
  cmd->add_option("--min_worker_ping_interval", s->min_worker_ping_interval_s,
                  "workers may ping at most this often (seconds; must not exceed their "
                  "--keepalive_time, or they are disconnected for pinging too often)")
      ->check(Between(0, 86400))
      ->capture_default_str();
}

}  // namespace juggle
