// The learner process: gRPC rollout service + PPO training loop + HTTP endpoints. Owns
// everything that must survive a worker's death: policy weights and version, observation
// normalizer, adaptive-walk edge counts, RNG, iteration and run progress, checkpointed
// atomically. This file assembles the parts: rollout_service.h (gRPC adapter),
// training_loop.h (the loop), its observers (run_log.h: <run_dir>/metrics.jsonl;
// learner_metrics.h: /metrics; dashboard_state.h), http_routes.h (HTTP).
//
// Threads: gRPC handler threads validate chunks and push them into the bounded ingestion
// queue (blocking up to a deadline when full: backpressure); Train() runs the training loop.
// Thread-safe as documented per method.
#ifndef JUGGLE_LEARNER_LEARNER_SERVER_H_
#define JUGGLE_LEARNER_LEARNER_SERVER_H_

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/connection_settings.h"
#include "common/metrics.h"
#include "common/transport_security.h"
#include "learner/training_observer.h"

namespace juggle {

struct LearnerOptions {
  LoadedConfig config;
  std::string run_dir;
  bool resume = false;
  int port = -1;          // -1: the config's service.port (0 = any free port)
  // HTTP port of /metrics and the dashboard: -1 the config's service.metrics_port; 0 off (as
  // in the config); kAnyFreePort a free port (tests, benchmarks); otherwise that port.
  static constexpr int kAnyFreePort = -2;
  int metrics_port = -1;
  bool listen_all_interfaces = true;   // gRPC on 0.0.0.0 (else 127.0.0.1)
  // HTTP (/metrics, dashboard) on 0.0.0.0; by default only on 127.0.0.1.
  bool http_all_interfaces = false;
  // Token and TLS of the gRPC service (common/transport_security.h); empty: none.
  TransportSecurity security;
  // Keepalive pings to workers and the ping policy enforced on them
  // (common/connection_settings.h).
  LearnerConnectionSettings connection;
  int64_t max_iterations = 0;   // 0: the config's ppo.iterations (0 = until stopped)
  double max_minutes = 0;
  // Told of every training event after the server's own observers (the run log
  // <run_dir>/metrics.jsonl, /metrics, the dashboard): e.g. the console line. Not owned; they
  // outlive Train.
  std::vector<TrainingObserver*> observers;
  // Benchmarks only: accept and count chunks but never train (measures ingestion alone).
  bool discard_data = false;
};

class LearnerServer {
 public:
  // Builds the env spec (every config or model error surfaces here, before any worker comes),
  // restores the newest readable checkpoint if `resume`, opens the run log and writes its
  // "run" record, starts the gRPC and HTTP servers. Errors: config/model/checkpoint problems,
  // a fresh run in a directory with checkpoints, a run log that cannot be written (named, with
  // the reason), ports in use.
  static absl::StatusOr<std::unique_ptr<LearnerServer>> Start(LearnerOptions options);
  ~LearnerServer();

  // Trains until `stop` is set, the iteration or time limit is reached. Checkpoints every
  // service.checkpoint_every iterations and once at the end. Call from one thread. Errors: a
  // checkpoint or a run-log write that failed (training stops there).
  absl::Status Train(const std::atomic<bool>* stop);

  // Stops the servers; Train must have returned. Idempotent.
  void Shutdown();

  int port() const;
  int metrics_port() const;
  int64_t version() const;
  // Chunks taken off the ingestion queue so far (including discarded ones).
  int64_t chunks_ingested() const;
  const Metrics& metrics() const;

 private:
  struct State;
  explicit LearnerServer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_SERVER_H_
