// The worker process's main loop: register with the learner, run the env pool with Eigen
// inference on the latest policy snapshot, stream contributions (one unroll per env), follow
// new snapshots, send heartbeats, reconnect with exponential backoff while the learner is
// away, and stop cleanly when `stop` is set. Holds no state that matters: killing it loses
// nothing the learner accepted.
#ifndef JUGGLE_WORKER_WORKER_CLIENT_H_
#define JUGGLE_WORKER_WORKER_CLIENT_H_

#include <atomic>
#include <cstdint>
#include <string>

#include "absl/status/status.h"
#include "common/connection_settings.h"
#include "common/transport_security.h"
#include "envs/labeller.h"

namespace juggle {

struct WorkerOptions {
  std::string learner_address;  // host:port
  int num_envs = 16;
  int num_threads = 2;
  int requested_slot = -1;       // -1: the learner picks
  const std::atomic<bool>* stop = nullptr;
  bool verbose = true;
  // Give up after this long without reaching the learner (0: never).
  double give_up_after_s = 0;
  // Token and TLS towards the learner (common/transport_security.h).
  TransportSecurity security;
  // Keepalive and reconnect backoff (common/connection_settings.h); max_reconnect_backoff_s
  // also caps the worker's own wait between sessions.
  WorkerConnectionSettings connection;
  // Builds the expert when the run's config asks for labels (ImitationConfig.label_envs > 0);
  // a run that asks for labels on a worker without one fails to start there (fatal).
  LabellerFactory labeller_factory;
  // Chunks written to the trajectory stream and not yet acknowledged, at most (1: wait for each
  // chunk's ack before the next, as before; docs/reliability.md "Chunks in flight"). Acks are
  // read beside the writes and new snapshots fetched beside the stream, so a round trip costs
  // a window, not a chunk. Synchronous runs drain the window after each contribution.
  int max_chunks_in_flight = 4;
};

// The range --max_chunks_in_flight accepts.
inline constexpr int kMaxChunksInFlightLimit = 256;

// Runs until *stop (OK) or give_up_after_s without a learner (UNAVAILABLE).
absl::Status RunWorker(const WorkerOptions& options);

}  // namespace juggle

#endif  // JUGGLE_WORKER_WORKER_CLIENT_H_
