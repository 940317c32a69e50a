#include "worker/worker_client.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include <grpcpp/grpcpp.h>

#include "absl/cleanup/cleanup.h"
#include "absl/strings/str_cat.h"
#include "common/chunk_codec.h"
#include "common/status_macros.h"
#include "common/eigen_policy.h"
#include "common/flat_parameters.h"
#include "envs/registry.h"
#include "proto/rollout.grpc.pb.h"
#include "worker/env_pool.h"
#include "worker/rollout_collector.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;
// Chunks stay below half the learner's message limit (service.max_chunk_mb) and 2 MiB.
size_t ChunkBytes(const config::RunConfig& run) {
  return std::min<size_t>(size_t{2} << 20, (size_t(std::max(1, run.service().max_chunk_mb())) << 20) / 2);
}

absl::Status FromGrpc(const grpc::Status& s, const std::string& what) {
  return absl::Status(static_cast<absl::StatusCode>(s.error_code()),
                      absl::StrCat(what, ": ", s.error_message()));
}

// Every call carries a deadline and, when the learner wants one, the token.
void PrepareContext(grpc::ClientContext* ctx, double seconds, const std::string& token) {
  if (seconds > 0) {
    ctx->set_deadline(std::chrono::system_clock::now() +
                      std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000)));
  }
  if (!token.empty()) ctx->AddMetadata(kAuthorizationHeader, BearerValue(token));
}

// Sleeps up to `seconds`, waking early when *stop is set.
void InterruptibleSleep(double seconds, const std::atomic<bool>* stop) {
  const auto until = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
  while (Clock::now() < until && !stop->load()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

struct Snapshot {
  int64_t version = -1;
  std::string params;
  std::vector<double> edge_counts;
};

// GetPolicy on `ctx` (prepared by the caller; it may cancel it from another thread).
absl::StatusOr<Snapshot> FetchPolicyOn(grpc::ClientContext* ctx, rpc::Rollout::Stub* stub,
                                       uint64_t incarnation, int64_t min_version) {
  rpc::PolicyRequest req;
  req.set_incarnation(incarnation);
  req.set_min_version(min_version);
  std::unique_ptr<grpc::ClientReader<rpc::PolicyChunk>> reader = stub->GetPolicy(ctx, req);
  Snapshot snap;
  rpc::PolicyChunk chunk;
  bool first = true;
  while (reader->Read(&chunk)) {
    if (first) {
      snap.version = chunk.version();
      snap.edge_counts.assign(chunk.edge_counts().begin(), chunk.edge_counts().end());
      snap.params.reserve(chunk.total_bytes());
      first = false;
    }
    snap.params += chunk.data();
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return FromGrpc(status, "GetPolicy");
  if (first) return absl::DataLossError("GetPolicy returned no snapshot");
  return snap;
}

absl::StatusOr<Snapshot> FetchPolicy(rpc::Rollout::Stub* stub, const std::string& token,
                                     uint64_t incarnation, int64_t min_version,
                                     double timeout_s) {
  grpc::ClientContext ctx;
  PrepareContext(&ctx, timeout_s + 5, token);
  return FetchPolicyOn(&ctx, stub, incarnation, min_version);
}

// A long-poll for the first snapshot newer than `min_version`, on its own thread while the
// worker simulates and streams (asynchronous mode): the learner answers as soon as it publishes
// one (or with the current one before the deadline), so a new version reaches the worker half
// a round trip after it exists and costs no stall. Cancelled (and joined) when destroyed.
class BackgroundFetch {
 public:
  BackgroundFetch(rpc::Rollout::Stub* stub, const std::string& token, uint64_t incarnation,
                  int64_t min_version) {
    PrepareContext(&ctx_, 15, token);
    thread_ = std::thread([this, stub, incarnation, min_version] {
      result_ = FetchPolicyOn(&ctx_, stub, incarnation, min_version);
      done_ = true;
    });
  }
  ~BackgroundFetch() {
    if (!done_) ctx_.TryCancel();
    thread_.join();
  }
  bool done() const { return done_; }
  // Waits for the answer (at most the call's deadline, or until *stop).
  absl::StatusOr<Snapshot> Take(const std::atomic<bool>* stop) {
    while (!done_ && !stop->load()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (!done_) {
      ctx_.TryCancel();
      thread_.join();
      thread_ = std::thread([] {});
    }
    return std::move(result_);
  }

 private:
  grpc::ClientContext ctx_;
  std::atomic<bool> done_{false};
  absl::StatusOr<Snapshot> result_ = absl::CancelledError("not fetched");
  std::thread thread_;
};

// What the learner acknowledged to this worker over all its sessions: the worker's side of
// the unroll accounts (docs/reliability.md, "Network faults").
struct AckCounts {
  int64_t unrolls = 0;   // unrolls in chunks the learner answered accepted
  int64_t chunks = 0;
  int64_t sessions = 0;  // registrations
};

// One connected session: from Register until an RPC fails or *stop. Returns OK on stop.
class Session {
 public:
  Session(const WorkerOptions& o, std::shared_ptr<grpc::Channel> channel, AckCounts* acks)
      : o_(o), stub_(rpc::Rollout::NewStub(channel)), acks_(acks) {}

  absl::Status Run() {
    rpc::RegisterResponse reg;
    {
      grpc::ClientContext ctx;
      PrepareContext(&ctx, 10, o_.security.token);
      rpc::RegisterRequest req;
      req.set_requested_slot(o_.requested_slot);
      req.set_num_envs(o_.num_envs);
      char host[256] = "";
      ::gethostname(host, sizeof(host) - 1);
      req.set_hostname(host);
      req.set_sessions_before(acks_->sessions);
      const grpc::Status s = stub_->Register(&ctx, req, &reg);
      // A wrong token or a request the learner's limits refuse will not change by retrying.
      if (s.error_code() == grpc::StatusCode::UNAUTHENTICATED ||
          s.error_code() == grpc::StatusCode::INVALID_ARGUMENT) {
        return Fatal(FromGrpc(s, "Register"));
      }
      if (!s.ok()) return FromGrpc(s, "Register");
    }
    registered_ = true;
    ++acks_->sessions;
    incarnation_ = reg.incarnation();
    // The learner built the same spec before it listened, so these fail only if this binary
    // differs from the learner's: retrying cannot help.
    absl::StatusOr<LoadedConfig> config = ParseRunConfig(reg.run_config(), "<from learner>");
    if (!config.ok()) return Fatal(config.status());
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec =
        CreateEnvSpecFromCompiled(*config, reg.model_mjb());
    if (!spec.ok()) return Fatal(spec.status());
    const config::RunConfig& run = config->run;
    absl::StatusOr<std::unique_ptr<EnvPool>> pool =
        EnvPool::Create(*spec, o_.num_envs, o_.num_threads, run.seed(), reg.slot());
    if (!pool.ok()) return Fatal(pool.status());
    (*pool)->set_apply_events_locally(false);  // the learner owns the edge counts
    RolloutCollector collector(pool->get(), reg.unroll_length(), run.seed(), reg.slot());
    collector.set_stop(o_.stop);
    std::unique_ptr<Labeller> labeller;
    if (const config::ImitationConfig& im = run.imitation(); im.label_envs() > 0) {
      if (!o_.labeller_factory) {
        return Fatal(absl::FailedPreconditionError(
            "the run asks for expert labels (imitation.label_envs) but this worker has no expert"));
      }
      absl::StatusOr<std::unique_ptr<Labeller>> made = o_.labeller_factory(*spec, *config, reg.slot());
      if (!made.ok()) return Fatal(made.status());
      labeller = std::move(*made);
      if (im.expert_envs() >= o_.num_envs) {
        return Fatal(absl::InvalidArgumentError(absl::StrCat(
            "imitation.expert_envs (", im.expert_envs(), ") leaves none of this worker's ",
            o_.num_envs, " envs to the policy")));
      }
      LabelPlan plan;
      plan.labeller = labeller.get();
      plan.label_envs = std::min(im.label_envs(), o_.num_envs);
      plan.expert_envs = std::min(im.expert_envs(), plan.label_envs);
      plan.expert_noise = im.expert_noise();
      collector.set_label_plan(plan);
    }
    if (o_.verbose) {
      std::printf("worker: registered as slot %d (incarnation %lx), %d envs on %d threads, %s mode\n",
                  reg.slot(), static_cast<unsigned long>(incarnation_), o_.num_envs,
                  o_.num_threads, reg.synchronous() ? "synchronous" : "asynchronous");
      std::fflush(stdout);
    }

    std::atomic<bool> session_over{false};
    std::atomic<bool> unknown{false};
    std::atomic<double> steps_per_s{0};
    std::atomic<int64_t> version_seen{-1};
    std::thread heartbeat([&] {
      while (!session_over && !o_.stop->load()) {
        grpc::ClientContext ctx;
        PrepareContext(&ctx, 2, o_.security.token);
        rpc::HeartbeatRequest req;
        rpc::HeartbeatResponse resp;
        req.set_incarnation(incarnation_);
        req.set_policy_version(version_seen);
        req.set_env_steps_per_s(steps_per_s);
        if (stub_->Heartbeat(&ctx, req, &resp).ok() && !resp.known()) unknown = true;
        InterruptibleSleep(1.0, &session_over);
      }
    });
    const absl::Status result = Loop(reg, run, pool->get(), &collector, &unknown, &steps_per_s, &version_seen);
    session_over = true;
    heartbeat.join();
    return result;
  }

  bool registered() const { return registered_; }
  // The session failed in a way a reconnect cannot fix (the learner's config does not build
  // here).
  bool fatal() const { return fatal_; }

 private:
  absl::Status Fatal(absl::Status status) {
    fatal_ = true;
    return absl::Status(status.code(),
                        absl::StrCat("the learner's run config does not build on this worker: ",
                                     status.message()));
  }

  // The chunks written and not yet acknowledged, oldest first, and what their acks said; the
  // acks are read on their own thread (StreamReader) while the loop writes.
  struct InFlight {
    int64_t sequence;
    int32_t num_unrolls;
  };
  struct Window {
    std::mutex mu;
    std::condition_variable cv;
    std::deque<InFlight> chunks;
    bool reader_done = false;     // the stream ended (or broke): no more acks
    int64_t latest_version = -1;  // the newest version any ack reported
    int64_t rejected_sequence = -1;  // the newest contribution with a refused chunk
    int64_t rejections = 0;
    std::string unregistered;     // set when the learner no longer knows this incarnation
  };

  void ReadAcks(grpc::ClientReaderWriter<rpc::TrajectoryChunk, rpc::ChunkAck>* stream, Window* w) {
    rpc::ChunkAck ack;
    while (stream->Read(&ack)) {
      std::lock_guard<std::mutex> lock(w->mu);
      if (w->chunks.empty()) break;  // an ack for nothing written: a confused learner
      const InFlight chunk = w->chunks.front();
      w->chunks.pop_front();
      w->latest_version = std::max(w->latest_version, ack.latest_version());
      if (ack.accepted()) {
        acks_->unrolls += chunk.num_unrolls;
        ++acks_->chunks;
      } else {
        if (o_.verbose) {
          std::fprintf(stderr, "worker: chunk rejected (%d): %s\n", ack.code(), ack.message().c_str());
        }
        if (ack.code() == static_cast<int>(absl::StatusCode::kFailedPrecondition) &&
            ack.message().find("unregistered") != std::string::npos) {
          w->unregistered = ack.message();
        }
        w->rejected_sequence = std::max(w->rejected_sequence, chunk.sequence);
        ++w->rejections;
      }
      w->cv.notify_all();
    }
    std::lock_guard<std::mutex> lock(w->mu);
    w->reader_done = true;
    w->cv.notify_all();
  }

  // Waits until fewer than `limit` chunks are unacknowledged (true), or the stream ended, the
  // learner forgot us, or *stop (false).
  bool WaitForRoom(Window* w, size_t limit) {
    std::unique_lock<std::mutex> lock(w->mu);
    while (w->chunks.size() >= limit && !w->reader_done && w->unregistered.empty() &&
           !o_.stop->load()) {
      w->cv.wait_for(lock, std::chrono::milliseconds(50));
    }
    return w->chunks.size() < limit && !w->reader_done && w->unregistered.empty();
  }

  absl::Status Loop(const rpc::RegisterResponse& reg, const config::RunConfig& run, EnvPool* pool,
                    RolloutCollector* collector, const std::atomic<bool>* unknown,
                    std::atomic<double>* steps_per_s, std::atomic<int64_t>* version_seen) {
    absl::StatusOr<Snapshot> snap = FetchPolicy(stub_.get(), o_.security.token, incarnation_, -1, 10);
    if (!snap.ok()) return snap.status();
    grpc::ClientContext stream_ctx;
    PrepareContext(&stream_ctx, 0, o_.security.token);
    std::unique_ptr<grpc::ClientReaderWriter<rpc::TrajectoryChunk, rpc::ChunkAck>> stream =
        stub_->StreamTrajectories(&stream_ctx);
    Window window;
    std::thread reader([&] { ReadAcks(stream.get(), &window); });
    std::unique_ptr<BackgroundFetch> fetch;
    // Every way out: acks still in flight are awaited (briefly: they are counted only when
    // they arrive), then the stream is cancelled and its reader joined.
    auto close_stream = [&](double drain_s) {
      fetch.reset();
      {
        std::unique_lock<std::mutex> lock(window.mu);
        window.cv.wait_for(lock, std::chrono::milliseconds(static_cast<int64_t>(drain_s * 1000)),
                           [&] { return window.reader_done; });
      }
      stream_ctx.TryCancel();
      reader.join();
    };
    // The stream broke: its status, once the reader is done with it.
    auto broken = [&]() -> absl::Status {
      std::string unregistered;
      {
        std::lock_guard<std::mutex> lock(window.mu);
        unregistered = window.unregistered;
      }
      close_stream(2);
      if (!unregistered.empty()) return absl::FailedPreconditionError(unregistered);
      return FromGrpc(stream->Finish(), "StreamTrajectories");
    };
    const size_t limit = static_cast<size_t>(std::max(1, o_.max_chunks_in_flight));
    // Versions a chunk may lag behind the learner's (asynchronous mode; the learner refuses
    // older ones, so a snapshot that far behind is replaced before simulating with it).
    const int64_t max_lag = reg.synchronous() ? 0 : run.service().max_policy_lag();
    Contribution contribution;
    int64_t sequence = 0;
    const int obs_dim = pool->obs_dim();
    while (!o_.stop->load()) {
      if (*unknown) {
        close_stream(0);
        return absl::FailedPreconditionError("the learner forgot this worker");
      }
      // Asynchronous: take a snapshot the long-poll brought meanwhile; wait for it only when
      // the one in hand is already beyond the allowed lag (its chunks would be refused). One
      // long-poll is always open.
      if (!reg.synchronous()) {
        int64_t latest;
        {
          std::lock_guard<std::mutex> lock(window.mu);
          latest = window.latest_version;
        }
        if (fetch && (fetch->done() || latest - snap->version > max_lag)) {
          absl::StatusOr<Snapshot> next = fetch->Take(o_.stop);
          fetch.reset();
          if (o_.stop->load()) break;
          // A long-poll past its deadline, or refused because the learner holds too many
          // (the service's max_concurrent_calls), is only opened again.
          if (!next.ok() && next.status().code() != absl::StatusCode::kDeadlineExceeded &&
              next.status().code() != absl::StatusCode::kResourceExhausted) {
            close_stream(0);
            return next.status();
          }
          if (next.ok() && next->version > snap->version) snap = std::move(next);
        }
        if (!fetch) {
          fetch = std::make_unique<BackgroundFetch>(stub_.get(), o_.security.token, incarnation_,
                                                    snap->version);
        }
      }
      absl::StatusOr<FlatParameters> params = FlatParameters::Deserialize(snap->params);
      if (!params.ok()) {
        close_stream(0);
        return params.status();
      }
      absl::StatusOr<EigenPolicy> policy =
          EigenPolicy::Create(run.model(), *params, obs_dim, pool->act_dim());
      if (!policy.ok()) {
        close_stream(0);
        return policy.status();
      }
      if (absl::Status s = pool->walk()->SetCounts(snap->edge_counts); !s.ok()) {
        close_stream(0);
        return s;
      }
      *version_seen = snap->version;

      // One contribution: an unroll of every env with this policy.
      const auto t0 = Clock::now();
      contribution.events.clear();
      const absl::Status collected = collector->Collect(*policy, &contribution.batch,
                                                        &contribution.events, &contribution.node);
      if (o_.stop->load()) break;  // a contribution cut short is dropped
      if (!collected.ok()) {
        close_stream(0);
        return collected;
      }
      contribution.stats = pool->TakeStats();
      contribution.expert_stats = pool->TakeSeparateStats();
      contribution.expert_cost = collector->TakeExpertCounters();
      *steps_per_s = contribution.batch.num_samples() /
                     std::max(1e-9, std::chrono::duration<double>(Clock::now() - t0).count());

      // Up to `limit` chunks unacknowledged; the parts after a refused one are not sent (the
      // rest of that contribution is useless).
      for (const rpc::TrajectoryChunk& chunk :
           EncodeContribution(contribution, incarnation_, sequence, ChunkBytes(run))) {
        if (!WaitForRoom(&window, limit)) {
          if (o_.stop->load()) break;
          return broken();
        }
        {
          std::lock_guard<std::mutex> lock(window.mu);
          if (window.rejected_sequence == sequence) break;
          window.chunks.push_back({sequence, chunk.num_unrolls()});
        }
        if (!stream->Write(chunk)) return broken();
      }
      if (o_.stop->load()) break;
      const int64_t this_sequence = sequence++;
      if (reg.synchronous()) {
        // Synchronous, as with one chunk in flight: every ack of this contribution first; after
        // an accepted contribution wait for the next version (the learner trains when every
        // worker's is in). A refused one (stale, full queue) is redone with the current policy,
        // or the learner would wait for it forever.
        if (!WaitForRoom(&window, 1)) {
          if (o_.stop->load()) break;
          return broken();
        }
        bool all_accepted;
        {
          std::lock_guard<std::mutex> lock(window.mu);
          all_accepted = window.rejected_sequence != this_sequence;
        }
        const bool wait_for_next = all_accepted;
        {  // (a refused contribution: the current snapshot, whatever its version)
          const int64_t have = snap->version;
          absl::StatusOr<Snapshot> next;
          do {
            next = FetchPolicy(stub_.get(), o_.security.token, incarnation_,
                               wait_for_next ? have : -1, 20);
            // A long update (cloning, a slow machine) outlasts one long-poll: poll again.
            if (!next.ok() && next.status().code() != absl::StatusCode::kDeadlineExceeded) {
              close_stream(0);
              return next.status();
            }
          } while (wait_for_next && (!next.ok() || next->version <= have) && !o_.stop->load() &&
                   !*unknown);
          if (next.ok()) snap = std::move(next);
        }
      }
    }
    // Stopping: no more chunks; the learner answers those in flight, then ends the stream.
    stream->WritesDone();
    close_stream(5);
    return absl::OkStatus();
  }

  const WorkerOptions& o_;
  std::unique_ptr<rpc::Rollout::Stub> stub_;
  AckCounts* acks_;
  uint64_t incarnation_ = 0;
  bool registered_ = false;
  bool fatal_ = false;
};

}  // namespace

absl::Status RunWorker(const WorkerOptions& options) {
  RETURN_IF_ERROR(Validate(options.connection));
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  ApplyTo(options.connection, &args);
  const double initial_backoff = options.connection.initial_reconnect_backoff_s;
  double backoff = initial_backoff;
  auto unreachable_since = Clock::now();
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials =
      MakeChannelCredentials(options.security);
  if (!credentials.ok()) return credentials.status();
  if (!options.security.server_name.empty()) {
    args.SetSslTargetNameOverride(options.security.server_name);
  }
  AckCounts acks;
  // The worker's side of the accounts, printed once at the end, however it ends.
  auto report = absl::MakeCleanup([&] {
    if (options.verbose) {
      std::printf("worker: the learner acknowledged %ld unrolls in %ld chunks over %ld sessions\n",
                  static_cast<long>(acks.unrolls), static_cast<long>(acks.chunks),
                  static_cast<long>(acks.sessions));
      std::fflush(stdout);
    }
  });
  while (!options.stop->load()) {
    auto channel = grpc::CreateCustomChannel(options.learner_address, *credentials, args);
    Session session(options, channel, &acks);
    const absl::Status status = session.Run();
    if (options.stop->load()) break;
    if (session.fatal()) return status;
    if (session.registered()) {
      backoff = initial_backoff;
      unreachable_since = Clock::now();
    }
    if (options.give_up_after_s > 0 &&
        std::chrono::duration<double>(Clock::now() - unreachable_since).count() > options.give_up_after_s) {
      return absl::UnavailableError(absl::StrCat("learner at ", options.learner_address,
                                                 " unreachable: ", status.message()));
    }
    if (options.verbose) {
      std::fprintf(stderr, "worker: %s; reconnecting in %.1f s\n",
                   std::string(status.message()).c_str(), backoff);
    }
    InterruptibleSleep(backoff, options.stop);
    backoff = std::min(backoff * 2, options.connection.max_reconnect_backoff_s);
  }
  return absl::OkStatus();
}

}  // namespace juggle
