// The learner process: gRPC rollout service + PPO training thread + /metrics endpoint.
// Owns everything that must survive a worker's death: policy weights and version, observation
// normalizer, adaptive-walk edge counts, RNG and iteration, checkpointed atomically.
//
// Threads: gRPC handler threads validate chunks and push them into the bounded ingestion
// queue (blocking up to a deadline when full: backpressure); Train() pops, assembles batches
// (synchronous or asynchronous mode), updates, publishes the new snapshot and checkpoints.
// Thread-safe as documented per method.
#ifndef JUGGLE_LEARNER_LEARNER_SERVER_H_
#define JUGGLE_LEARNER_LEARNER_SERVER_H_

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/metrics.h"

namespace juggle {

// What one training iteration did (for progress lines and metrics files).
struct IterationReport {
  int64_t iteration = 0;
  int64_t total_samples = 0;
  int64_t samples = 0;
  double samples_per_s = 0;       // over the iteration's wall time
  double sim_s_per_s = 0;
  double mean_return = 0;
  double mean_episode_len = 0;
  double completions_per_episode = 0;
  int64_t episodes = 0;
  double mean_policy_lag = 0;
  double iteration_s = 0;         // wall time since the previous iteration ended
  double wait_s = 0;              // of which waiting for data
  double update_s = 0;            // of which the PPO update
  int workers = 0;
  double value_loss = 0, approx_kl = 0, actor_lr = 0;
  std::string ToJson() const;
  std::string ToLine() const;
};

struct LearnerOptions {
  LoadedConfig config;
  std::string run_dir;
  bool resume = false;
  int port = -1;          // -1: the config's service.port (0 = any free port)
  int metrics_port = -1;  // -1: the config's service.metrics_port (0 = off)
  bool listen_all_interfaces = true;
  int64_t max_iterations = 0;   // 0: the config's ppo.iterations (0 = until stopped)
  double max_minutes = 0;
  std::function<void(const IterationReport&)> on_iteration;
  // Benchmarks only: accept and count chunks but never train (measures ingestion alone).
  bool discard_data = false;
};

class LearnerServer {
 public:
  // Loads the model, restores the newest readable checkpoint if `resume`, starts the gRPC and
  // metrics servers. Errors: config/model/checkpoint problems, ports in use.
  static absl::StatusOr<std::unique_ptr<LearnerServer>> Start(LearnerOptions options);
  ~LearnerServer();

  // Trains until `stop` is set, the iteration or time limit is reached. Checkpoints every
  // service.checkpoint_every iterations and once at the end. Call from one thread.
  absl::Status Train(const std::atomic<bool>* stop);

  // Stops the servers; Train must have returned. Idempotent.
  void Shutdown();

  int port() const;
  int metrics_port() const;
  int64_t version() const;
  // Chunks taken off the ingestion queue so far (including discarded ones).
  int64_t chunks_ingested() const;
  const Metrics& metrics() const;

  struct State;

 private:
  explicit LearnerServer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_SERVER_H_
