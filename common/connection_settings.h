// Keepalive and reconnect settings of the rollout service's gRPC connections, on the worker's
// channel and on the learner's server (docs/reliability.md, "Network faults").
//
// Why: gRPC's client keepalive is off by default, so a connection that a middlebox or a
// partition drops silently is never noticed: a worker would wait on its stream forever. With
// keepalive on, a worker whose connection stops answering sees its calls fail within
// keepalive_time + keepalive_timeout (its next ping goes unanswered), and reconnects; the
// learner, pinging its side, closes connections of workers that vanished the same way.
//
// Contract between the two sides: the learner refuses pings from a worker that come more often
// than its min_worker_ping_interval (after two strikes it sends GOAWAY and the worker
// reconnects), so a worker's keepalive_time must be >= the learner's min_worker_ping_interval.
// Thread-safety: plain values.
#ifndef JUGGLE_COMMON_CONNECTION_SETTINGS_H_
#define JUGGLE_COMMON_CONNECTION_SETTINGS_H_

#include "absl/status/status.h"
#include "grpcpp/server_builder.h"
#include "grpcpp/support/channel_arguments.h"

namespace juggle {

// The worker's channel to the learner.
struct WorkerConnectionSettings {
  // Seconds between keepalive pings on the worker's connection (0: keepalive off, as gRPC's
  // default), and how long a ping may go unanswered before the connection is closed.
  double keepalive_time_s = 10;
  double keepalive_timeout_s = 5;
  // Ping even while no call is open (the worker nearly always has one open: its stream).
  bool permit_without_calls = true;
  // Reconnect backoff: the first retry after this, then x1.6 (gRPC) or x2 (the worker's own
  // session loop) up to max_reconnect_backoff_s. gRPC's defaults are 1 s and 120 s.
  double initial_reconnect_backoff_s = 0.1;
  double max_reconnect_backoff_s = 5;
  // The shortest time one connection attempt (TCP, TLS and HTTP/2 handshakes) may take before
  // it is abandoned. gRPC's default is 20 s; against a peer whose SYNs are dropped this is the
  // time one attempt can hang.
  double min_connect_timeout_s = 5;
};

// The learner's server.
struct LearnerConnectionSettings {
  // Seconds between the learner's pings on each worker connection (0: off), and how long a
  // ping may go unanswered before the connection is closed (gRPC's server default: 2 h, 20 s).
  double keepalive_time_s = 30;
  double keepalive_timeout_s = 10;
  // Pings from a worker more often than this are strikes (gRPC's default: 300 s, which would
  // make every worker with keepalive_time below 5 minutes lose its connection).
  double min_worker_ping_interval_s = 5;
};

// INVALID_ARGUMENT naming the setting (by its flag name) when a value is out of range:
// keepalive_time 0 or in [0.5, 86400] s; keepalive_timeout in [0.5, 3600] s; backoffs in
// [0.01, 3600] s with initial <= max; min_connect_timeout in [0.1, 3600] s;
// min_worker_ping_interval in [0, 86400] s.
absl::Status Validate(const WorkerConnectionSettings& settings);
absl::Status Validate(const LearnerConnectionSettings& settings);

// The gRPC channel arguments for `settings` (GRPC_ARG_KEEPALIVE_*, GRPC_ARG_HTTP2_MAX_PINGS_
// WITHOUT_DATA = 0 so pings go on while the stream is idle, reconnect backoffs, min connect
// timeout). REQUIRES: Validate(settings).ok().
void ApplyTo(const WorkerConnectionSettings& settings, grpc::ChannelArguments* args);
// The server's arguments: its keepalive pings and the ping policy it enforces on workers.
// REQUIRES: Validate(settings).ok().
void ApplyTo(const LearnerConnectionSettings& settings, grpc::ServerBuilder* builder);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CONNECTION_SETTINGS_H_
