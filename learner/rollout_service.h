// The gRPC adapter of proto/rollout.proto on the learner: checks the token, registers workers
// (within the registry's limits), validates chunks and enqueues them (backpressure: a full
// queue blocks the stream up to 30 s), serves policy snapshots (long-poll up to 30 s) and
// heartbeats. Holds no training state.
// Thread-safe: gRPC calls it from many threads; everything it uses is thread-safe or immutable.
#ifndef JUGGLE_LEARNER_ROLLOUT_SERVICE_H_
#define JUGGLE_LEARNER_ROLLOUT_SERVICE_H_

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

#include "absl/status/status.h"
#include "common/bounded_queue.h"
#include "common/metrics.h"
#include "envs/stored_config.h"
#include "learner/broadcast_tracker.h"
#include "learner/contribution_assembler.h"
#include "learner/policy_store.h"
#include "learner/worker_registry.h"
#include "proto/rollout.grpc.pb.h"

namespace juggle {

// What every worker is told at registration, and the shapes its chunks must have. Immutable.
struct WorkerBootstrap {
  StoredConfig config;      // the run config, every file it names inlined, and the model
  bool synchronous = true;
  int max_policy_lag = 0;   // versions a chunk may lag (0 in synchronous mode)
  int unroll_length = 0;
  int obs_dim = 0, act_dim = 0, num_nodes = 0, num_edges = 0;
};

class RolloutService final : public rpc::Rollout::Service {
 public:
  struct Deps {  // all outlive the service
    WorkerRegistry* registry;
    PolicyStore* store;
    BoundedQueue<ChunkPart>* queue;
    Metrics* metrics;
    const WorkerBootstrap* bootstrap;
    // Every RPC must carry "authorization: Bearer <token>" (UNAUTHENTICATED otherwise); empty:
    // no token required.
    std::string auth_token;
    // Concurrent long-lived calls (open trajectory streams; GetPolicy long-polls) each holds a
    // server thread: beyond this many of each kind, new ones get RESOURCE_EXHAUSTED at once.
    int max_concurrent_calls = 512;
    // Measures each version's broadcast (juggle_policy_broadcast_seconds); null: not measured.
    BroadcastTracker* broadcast = nullptr;
  };
  explicit RolloutService(Deps deps) : d_(deps) {}

  grpc::Status Register(grpc::ServerContext* context, const rpc::RegisterRequest* request,
                        rpc::RegisterResponse* response) override;
  grpc::Status StreamTrajectories(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<rpc::ChunkAck, rpc::TrajectoryChunk>* stream) override;
  grpc::Status GetPolicy(grpc::ServerContext* context, const rpc::PolicyRequest* request,
                         grpc::ServerWriter<rpc::PolicyChunk>* writer) override;
  grpc::Status Heartbeat(grpc::ServerContext* context, const rpc::HeartbeatRequest* request,
                         rpc::HeartbeatResponse* response) override;

  // The ingest rules for one chunk, as StreamTrajectories applies them: OK and enqueued, or
  // FAILED_PRECONDITION (unregistered incarnation, version ahead of the learner or beyond the
  // allowed lag), INVALID_ARGUMENT (shapes, values), RESOURCE_EXHAUSTED (queue full for 30 s).
  // Rejections are counted in juggle_chunks_rejected_total by reason, and every chunk of a
  // registered worker in its WorkerInfo (accepted or rejected).
  absl::Status Ingest(const rpc::TrajectoryChunk& chunk);

 private:
  absl::Status IngestChunk(const rpc::TrajectoryChunk& chunk);  // Ingest, before counting
  absl::Status Reject(const std::string& reason, absl::Status status);
  // OK, or UNAUTHENTICATED (counted) when the call lacks the token.
  grpc::Status Authorize(const grpc::ServerContext* context, const char* rpc);
  int64_t current_version() const { return d_.store->Current()->version; }

  Deps d_;
  std::atomic<int> open_streams_{0}, waiting_polls_{0};
  // Invalid chunks are also reported on stderr, at most once per 10 s (Reject).
  std::mutex warn_mu_;
  std::chrono::steady_clock::time_point last_invalid_warning_{};
  int64_t invalid_since_warning_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_ROLLOUT_SERVICE_H_
