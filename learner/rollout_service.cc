#include "learner/rollout_service.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "absl/strings/str_cat.h"
#include "common/chunk_codec.h"
#include "common/transport_security.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

grpc::Status ToGrpc(const absl::Status& s) {
  return grpc::Status(static_cast<grpc::StatusCode>(s.code()), std::string(s.message()));
}

// Counts one in-flight call of a kind for its lifetime; admitted() is false beyond the limit.
class CallSlot {
 public:
  CallSlot(std::atomic<int>* count, int limit) : count_(count) {
    admitted_ = count_->fetch_add(1) < limit;
  }
  ~CallSlot() { count_->fetch_sub(1); }
  bool admitted() const { return admitted_; }

 private:
  std::atomic<int>* count_;
  bool admitted_;
};

}  // namespace

grpc::Status RolloutService::Authorize(const grpc::ServerContext* ctx, const char* rpc) {
  if (d_.auth_token.empty()) return grpc::Status::OK;
  const auto& metadata = ctx->client_metadata();
  const auto it = metadata.find(kAuthorizationHeader);
  const std::string header = it == metadata.end() ? std::string()
                                                  : std::string(it->second.data(), it->second.size());
  if (TokenMatches(d_.auth_token, header)) return grpc::Status::OK;
  d_.metrics->Add("juggle_rpcs_unauthenticated_total", 1, {{"rpc", rpc}});
  return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                      it == metadata.end() ? "this learner requires a token (--token_file or "
                                             "$JUGGLE_TOKEN)"
                                           : "wrong token");
}

grpc::Status RolloutService::Register(grpc::ServerContext* ctx, const rpc::RegisterRequest* req,
                                      rpc::RegisterResponse* resp) {
  if (grpc::Status auth = Authorize(ctx, "Register"); !auth.ok()) return auth;
  std::optional<uint64_t> replaced;
  const absl::StatusOr<WorkerInfo> registered = d_.registry->Register(
      req->requested_slot(), req->num_envs(), req->hostname(), Clock::now(), &replaced,
      req->sessions_before());
  if (!registered.ok()) {
    d_.metrics->Add("juggle_registrations_rejected_total", 1,
                    {{"reason", registered.status().code() == absl::StatusCode::kResourceExhausted
                                    ? "limit"
                                    : "invalid"}});
    return ToGrpc(registered.status());
  }
  const WorkerInfo& w = *registered;
  if (replaced) d_.metrics->Add("juggle_worker_restarts_total", 1);
  if (w.sessions > 1) {
    d_.metrics->Add("juggle_worker_reconnects_total", 1, {{"slot", std::to_string(w.slot)}});
  }
  const WorkerBootstrap& b = *d_.bootstrap;
  resp->set_slot(w.slot);
  resp->set_incarnation(w.incarnation);
  resp->set_run_config(b.config.text);
  resp->set_model_mjb(b.config.model_mjb);
  resp->set_synchronous(b.synchronous);
  resp->set_unroll_length(b.unroll_length);
  std::printf("worker slot %d registered (incarnation %lx, %d envs, host %s, session %ld)\n",
              w.slot, static_cast<unsigned long>(w.incarnation), w.num_envs,
              req->hostname().c_str(), static_cast<long>(w.sessions));
  std::fflush(stdout);
  return grpc::Status::OK;
}

grpc::Status RolloutService::StreamTrajectories(
    grpc::ServerContext* ctx, grpc::ServerReaderWriter<rpc::ChunkAck, rpc::TrajectoryChunk>* stream) {
  if (grpc::Status auth = Authorize(ctx, "StreamTrajectories"); !auth.ok()) return auth;
  const CallSlot slot(&open_streams_, d_.max_concurrent_calls);
  if (!slot.admitted()) {
    d_.metrics->Add("juggle_calls_refused_total", 1, {{"rpc", "StreamTrajectories"}});
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        absl::StrCat("more than ", d_.max_concurrent_calls, " open trajectory streams"));
  }
  rpc::TrajectoryChunk chunk;
  while (stream->Read(&chunk)) {
    rpc::ChunkAck ack;
    const absl::Status status = Ingest(chunk);
    ack.set_accepted(status.ok());
    ack.set_code(static_cast<int>(status.code()));
    ack.set_message(std::string(status.message()));
    ack.set_latest_version(current_version());
    if (!stream->Write(ack)) break;
  }
  return grpc::Status::OK;
}

grpc::Status RolloutService::GetPolicy(grpc::ServerContext* ctx, const rpc::PolicyRequest* req,
                                       grpc::ServerWriter<rpc::PolicyChunk>* writer) {
  if (grpc::Status auth = Authorize(ctx, "GetPolicy"); !auth.ok()) return auth;
  if (!d_.registry->Find(req->incarnation())) {
    d_.metrics->Add("juggle_policy_requests_rejected_total", 1, {{"reason", "unregistered"}});
    return ToGrpc(absl::FailedPreconditionError(absl::StrCat(
        "unregistered incarnation ", req->incarnation(), ": call Register first")));
  }
  // A version the learner has not reached cannot be waited for: versions only come from this
  // learner, so a request beyond the next one is a confused or hostile client.
  if (const int64_t current = current_version(); req->min_version() > current) {
    d_.metrics->Add("juggle_policy_requests_rejected_total", 1, {{"reason", "future_version"}});
    return ToGrpc(absl::OutOfRangeError(absl::StrCat(
        "min_version ", req->min_version(), " is ahead of the learner's version ", current)));
  }
  const CallSlot slot(&waiting_polls_, d_.max_concurrent_calls);
  if (req->min_version() >= 0 && !slot.admitted()) {
    d_.metrics->Add("juggle_calls_refused_total", 1, {{"rpc", "GetPolicy"}});
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        absl::StrCat("more than ", d_.max_concurrent_calls, " policy long-polls waiting"));
  }
  // Answer (with the current snapshot, if nothing newer came) a little before the caller's
  // deadline: an answer at the deadline itself reaches a caller that has given up.
  const auto deadline = std::min(ctx->deadline() - std::chrono::seconds(2),
                                 std::chrono::system_clock::now() + std::chrono::seconds(30));
  const auto steady_deadline = Clock::now() + (deadline - std::chrono::system_clock::now());
  std::shared_ptr<const PolicySnapshot> snap =
      req->min_version() < 0 ? d_.store->Current()
                             : d_.store->WaitNewer(req->min_version(), steady_deadline);
  constexpr size_t kChunk = 1 << 20;
  size_t offset = 0;
  bool first = true;
  do {
    rpc::PolicyChunk out;
    if (first) {
      out.set_version(snap->version);
      out.set_total_bytes(static_cast<int64_t>(snap->params.size()));
      for (double c : snap->edge_counts) out.add_edge_counts(c);
      first = false;
    }
    const size_t n = std::min(kChunk, snap->params.size() - offset);
    out.set_data(snap->params.substr(offset, n));
    offset += n;
    if (!writer->Write(out)) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
  } while (offset < snap->params.size());
  if (d_.broadcast) {
    for (double seconds : d_.broadcast->Delivered(
             req->incarnation(), snap->version, Clock::now(),
             [this](uint64_t incarnation) { return d_.registry->Find(incarnation).has_value(); })) {
      d_.metrics->Observe("juggle_policy_broadcast_seconds", seconds);
    }
  }
  return grpc::Status::OK;
}

grpc::Status RolloutService::Heartbeat(grpc::ServerContext* ctx, const rpc::HeartbeatRequest* req,
                                       rpc::HeartbeatResponse* resp) {
  if (grpc::Status auth = Authorize(ctx, "Heartbeat"); !auth.ok()) return auth;
  resp->set_known(d_.registry->Touch(req->incarnation(), Clock::now(), req->policy_version(),
                                     req->env_steps_per_s()));
  resp->set_latest_version(current_version());
  return grpc::Status::OK;
}

absl::Status RolloutService::Reject(const std::string& reason, absl::Status status) {
  d_.metrics->Add("juggle_chunks_rejected_total", 1, {{"reason", reason}});
  if (reason == "invalid") {
    // A worker whose every chunk is refused would otherwise stall the run without a word.
    std::lock_guard<std::mutex> lock(warn_mu_);
    ++invalid_since_warning_;
    const Clock::time_point now = Clock::now();
    if (now - last_invalid_warning_ >= std::chrono::seconds(10)) {
      std::fprintf(stderr, "warning: rejected %ld invalid chunk(s) since the last warning: %s\n",
                   static_cast<long>(invalid_since_warning_),
                   std::string(status.message()).c_str());
      last_invalid_warning_ = now;
      invalid_since_warning_ = 0;
    }
  }
  return status;
}

absl::Status RolloutService::Ingest(const rpc::TrajectoryChunk& chunk) {
  const absl::Status status = IngestChunk(chunk);
  // A version the learner has not published is a peer's claim, not a sign of progress.
  const int64_t version = chunk.policy_version() <= current_version() ? chunk.policy_version() : -1;
  d_.registry->CountChunk(chunk.incarnation(), status.ok(), version);
  return status;
}

absl::Status RolloutService::IngestChunk(const rpc::TrajectoryChunk& chunk) {
  const WorkerBootstrap& b = *d_.bootstrap;
  const std::optional<WorkerInfo> worker = d_.registry->Find(chunk.incarnation());
  if (!worker) {
    return Reject("unregistered",
                  absl::FailedPreconditionError(absl::StrCat(
                      "unregistered incarnation ", chunk.incarnation(), ": call Register first")));
  }
  d_.registry->Touch(chunk.incarnation(), Clock::now());
  const int64_t current = current_version();
  if (chunk.policy_version() > current) {
    return Reject("unknown_version", absl::FailedPreconditionError(absl::StrCat(
                                         "chunk policy version ", chunk.policy_version(),
                                         " is newer than the learner's ", current)));
  }
  if (chunk.policy_version() < current - b.max_policy_lag) {
    // Counts the unrolls the chunk carries, not the number it claims.
    const int64_t carried =
        chunk.unroll_length() > 0 ? chunk.rewards_size() / chunk.unroll_length() : 0;
    d_.metrics->Add("juggle_unrolls_rejected_total",
                    static_cast<double>(std::clamp<int64_t>(chunk.num_unrolls(), 0, carried)),
                    {{"reason", "stale"}});
    return Reject("stale_version", absl::FailedPreconditionError(absl::StrCat(
                                       "chunk policy version ", chunk.policy_version(),
                                       " is more than ", b.max_policy_lag,
                                       " behind the learner's ", current)));
  }
  if (chunk.unroll_length() != b.unroll_length) {
    return Reject("invalid", absl::InvalidArgumentError(
                                 absl::StrCat("chunk unroll_length ", chunk.unroll_length(),
                                              " differs from the run's ", b.unroll_length)));
  }
  // One contribution holds one unroll per env of the worker, in at most that many parts.
  if (chunk.num_unrolls() > worker->num_envs || chunk.num_parts() > worker->num_envs) {
    return Reject("invalid", absl::InvalidArgumentError(absl::StrCat(
                                 "chunk claims ", chunk.num_unrolls(), " unrolls in part ",
                                 chunk.part(), " of ", chunk.num_parts(), "; the worker registered ",
                                 worker->num_envs, " envs")));
  }
  absl::StatusOr<Contribution> decoded =
      DecodeChunk(chunk, b.obs_dim, b.act_dim, b.num_nodes, b.num_edges);
  if (!decoded.ok()) return Reject("invalid", decoded.status());
  ChunkPart part;
  part.slot = worker->slot;
  part.incarnation = chunk.incarnation();
  part.sequence = chunk.sequence();
  part.part = chunk.part();
  part.num_parts = chunk.num_parts();
  part.version = chunk.policy_version();
  part.max_unrolls = worker->num_envs;
  part.data = std::move(*decoded);
  if (!d_.queue->Push(std::move(part), Clock::now() + std::chrono::seconds(30))) {
    return Reject("queue_full", absl::ResourceExhaustedError(
                                    "the learner's ingestion queue stayed full for 30 s"));
  }
  d_.metrics->Add("juggle_unrolls_accepted_total", chunk.num_unrolls());
  d_.metrics->Set("juggle_ingest_queue_chunks", static_cast<double>(d_.queue->size()));
  return absl::OkStatus();
}

}  // namespace juggle
