#include "common/connection_settings.h"

#include <cmath>
#include <cstdint>
#include <string>

#include <grpc/grpc.h>

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

absl::Status CheckRange(const char* flag, double value, double lo, double hi) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    return absl::InvalidArgumentError(
        absl::StrCat("--", flag, "=", value, " is outside [", lo, ", ", hi, "] seconds"));
  }
  return absl::OkStatus();
}

absl::Status CheckKeepalive(double time_s, double timeout_s) {
  if (time_s != 0) {
    if (absl::Status s = CheckRange("keepalive_time", time_s, 0.5, 86400); !s.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(s.message(), " (0 turns keepalive off)"));
    }
  }
  return CheckRange("keepalive_timeout", timeout_s, 0.5, 3600);
}

int Ms(double seconds) { return static_cast<int>(std::lround(seconds * 1000)); }

}  // namespace

absl::Status Validate(const WorkerConnectionSettings& s) {
  if (absl::Status e = CheckKeepalive(s.keepalive_time_s, s.keepalive_timeout_s); !e.ok()) return e;
  if (absl::Status e = CheckRange("initial_reconnect_backoff", s.initial_reconnect_backoff_s, 0.01, 3600);
      !e.ok()) {
    return e;
  }
  if (absl::Status e = CheckRange("max_reconnect_backoff", s.max_reconnect_backoff_s, 0.01, 3600);
      !e.ok()) {
    return e;
  }
  if (s.initial_reconnect_backoff_s > s.max_reconnect_backoff_s) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--max_reconnect_backoff=", s.max_reconnect_backoff_s,
        " is below the initial reconnect backoff (", s.initial_reconnect_backoff_s, " s)"));
  }
  return CheckRange("min_connect_timeout", s.min_connect_timeout_s, 0.1, 3600);
}

absl::Status Validate(const LearnerConnectionSettings& s) {
  if (absl::Status e = CheckKeepalive(s.keepalive_time_s, s.keepalive_timeout_s); !e.ok()) return e;
  return CheckRange("min_worker_ping_interval", s.min_worker_ping_interval_s, 0, 86400);
}

void ApplyTo(const WorkerConnectionSettings& s, grpc::ChannelArguments* args) {
  if (s.keepalive_time_s > 0) {
    args->SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, Ms(s.keepalive_time_s));
    args->SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, Ms(s.keepalive_timeout_s));
    args->SetInt(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, s.permit_without_calls ? 1 : 0);
    // Without this, gRPC stops pinging after two pings with no data sent in between: a worker
    // waiting on an ack would stop checking its connection.
    args->SetInt(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  }
  args->SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, Ms(s.initial_reconnect_backoff_s));
  args->SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, Ms(s.max_reconnect_backoff_s));
  // gRPC's subchannel reads its minimum connect timeout (default 20 s) from this argument,
  // despite the name (doc/connection-backoff.md: MIN_CONNECT_TIMEOUT).
  args->SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, Ms(s.min_connect_timeout_s));
}

void ApplyTo(const LearnerConnectionSettings& s, grpc::ServerBuilder* builder) {
  if (s.keepalive_time_s > 0) {
    builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, Ms(s.keepalive_time_s));
    builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, Ms(s.keepalive_timeout_s));
    builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
    builder->AddChannelArgument(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  }
  // The ping policy enforced on workers: pings at most this often, with or without calls.
  builder->AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS,
                              Ms(s.min_worker_ping_interval_s));
  builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
}

}  // namespace juggle
