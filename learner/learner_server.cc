#include "learner/learner_server.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <random>
#include <thread>

#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <mujoco/mujoco.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/adaptive_walk.h"
#include "common/bounded_queue.h"
#include "common/chunk_codec.h"
#include "common/http_server.h"
#include "common/env_family.h"
#include "common/outcome.h"
#include "common/status_macros.h"
#include "google/protobuf/text_format.h"
#include "learner/checkpoint.h"
#include "learner/contribution_assembler.h"
#include "learner/learner_state.h"
#include "learner/policy_store.h"
#include "learner/ppo_trainer.h"
#include "learner/worker_registry.h"
#include "proto/rollout.grpc.pb.h"

namespace juggle {

using Clock = std::chrono::steady_clock;

std::string IterationReport::ToJson() const {
  return absl::StrFormat(
      "{\"iteration\": %d, \"samples\": %d, \"samples_per_s\": %.1f, \"sim_s_per_s\": %.2f, "
      "\"mean_return\": %.4f, \"mean_episode_len\": %.2f, \"completions_per_episode\": %.3f, "
      "\"episodes\": %d, \"policy_lag\": %.3f, \"iteration_s\": %.3f, \"wait_s\": %.3f, "
      "\"update_s\": %.3f, \"workers\": %d, \"value_loss\": %.5f, \"approx_kl\": %.5f, "
      "\"actor_lr\": %.6f}",
      iteration, total_samples, samples_per_s, sim_s_per_s, mean_return, mean_episode_len,
      completions_per_episode, episodes, mean_policy_lag, iteration_s, wait_s, update_s, workers,
      value_loss, approx_kl, actor_lr);
}

std::string IterationReport::ToLine() const {
  return absl::StrFormat(
      "iter %5d  samples %9d  %7.0f samples/s  %5.1f sim-s/s  return %7.3f  ep_len %6.1f  "
      "completions/ep %5.2f  lag %.2f  workers %d  %.2fs (wait %.2f, update %.2f)",
      iteration, total_samples, samples_per_s, sim_s_per_s, mean_return, mean_episode_len,
      completions_per_episode, mean_policy_lag, workers, iteration_s, wait_s, update_s);
}

struct LearnerServer::State {
  LearnerOptions options;
  const config::RunConfig* run = nullptr;
  int obs_dim = 0, act_dim = 0, num_nodes = 0, num_edges = 0;
  double control_dt = 0;
  std::string model_mjb;
  std::string config_text;  // graph inline, for workers
  std::unique_ptr<PpoTrainer> trainer;
  std::unique_ptr<AdaptiveWalk> walk;
  std::unique_ptr<WorkerRegistry> registry;
  std::unique_ptr<BoundedQueue<ChunkPart>> queue;
  PolicyStore store;
  Metrics metrics;
  std::unique_ptr<CheckpointDir> checkpoints;
  std::unique_ptr<grpc::Server> grpc_server;
  std::unique_ptr<grpc::Service> service;
  std::unique_ptr<HttpServer> http;
  int port = 0;
  bool shut_down = false;
  std::atomic<int64_t> chunks_ingested{0};

  void PublishSnapshot() {
    auto snap = std::make_shared<PolicySnapshot>();
    snap->version = trainer->version();
    snap->params = trainer->ExportPolicy().Serialize();
    snap->edge_counts = walk->counts();
    store.Publish(std::move(snap));
    metrics.Set("juggle_policy_version", static_cast<double>(trainer->version()));
  }
  int64_t current_version() const { return store.Current()->version; }
  absl::Status Checkpoint() {
    absl::StatusOr<std::string> path = checkpoints->Save(
        trainer->iteration(), SaveLearnerState(options.config, *trainer, *walk));
    return path.ok() ? absl::OkStatus() : path.status();
  }
};

namespace {

grpc::Status ToGrpc(const absl::Status& s) {
  return grpc::Status(static_cast<grpc::StatusCode>(s.code()), std::string(s.message()));
}

class RolloutServiceImpl final : public rpc::Rollout::Service {
 public:
  explicit RolloutServiceImpl(LearnerServer::State* s) : s_(s) {}

  grpc::Status Register(grpc::ServerContext*, const rpc::RegisterRequest* req,
                        rpc::RegisterResponse* resp) override {
    if (req->num_envs() < 1) {
      return ToGrpc(absl::InvalidArgumentError("register: num_envs must be >= 1"));
    }
    std::optional<uint64_t> replaced;
    const WorkerInfo w = s_->registry->Register(req->requested_slot(), req->num_envs(),
                                                req->hostname(), Clock::now(), &replaced);
    if (replaced) s_->metrics.Add("juggle_worker_restarts_total", 1);
    resp->set_slot(w.slot);
    resp->set_incarnation(w.incarnation);
    resp->set_run_config(s_->config_text);
    resp->set_model_mjb(s_->model_mjb);
    resp->set_synchronous(s_->run->service().synchronous());
    resp->set_unroll_length(s_->run->ppo().unroll_length());
    std::printf("worker slot %d registered (incarnation %lx, %d envs, host %s)\n", w.slot,
                static_cast<unsigned long>(w.incarnation), w.num_envs, req->hostname().c_str());
    std::fflush(stdout);
    return grpc::Status::OK;
  }

  grpc::Status StreamTrajectories(
      grpc::ServerContext*,
      grpc::ServerReaderWriter<rpc::ChunkAck, rpc::TrajectoryChunk>* stream) override {
    rpc::TrajectoryChunk chunk;
    while (stream->Read(&chunk)) {
      rpc::ChunkAck ack;
      const absl::Status status = Ingest(chunk);
      ack.set_accepted(status.ok());
      ack.set_code(static_cast<int>(status.code()));
      ack.set_message(std::string(status.message()));
      ack.set_latest_version(s_->current_version());
      if (!stream->Write(ack)) break;
    }
    return grpc::Status::OK;
  }

  grpc::Status GetPolicy(grpc::ServerContext* ctx, const rpc::PolicyRequest* req,
                         grpc::ServerWriter<rpc::PolicyChunk>* writer) override {
    if (!s_->registry->Find(req->incarnation())) {
      s_->metrics.Add("juggle_policy_requests_rejected_total", 1, {{"reason", "unregistered"}});
      return ToGrpc(absl::FailedPreconditionError(absl::StrCat(
          "unregistered incarnation ", req->incarnation(), ": call Register first")));
    }
    auto deadline = std::min(ctx->deadline(), std::chrono::system_clock::now() + std::chrono::seconds(30));
    const auto steady_deadline =
        Clock::now() + (deadline - std::chrono::system_clock::now());
    std::shared_ptr<const PolicySnapshot> snap =
        req->min_version() < 0 ? s_->store.Current()
                               : s_->store.WaitNewer(req->min_version(), steady_deadline);
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
    return grpc::Status::OK;
  }

  grpc::Status Heartbeat(grpc::ServerContext*, const rpc::HeartbeatRequest* req,
                         rpc::HeartbeatResponse* resp) override {
    resp->set_known(s_->registry->Touch(req->incarnation(), Clock::now(), req->policy_version(),
                                        req->env_steps_per_s()));
    resp->set_latest_version(s_->current_version());
    return grpc::Status::OK;
  }

 private:
  absl::Status Reject(const std::string& reason, absl::Status status) {
    s_->metrics.Add("juggle_chunks_rejected_total", 1, {{"reason", reason}});
    return status;
  }

  absl::Status Ingest(const rpc::TrajectoryChunk& chunk) {
    const std::optional<WorkerInfo> worker = s_->registry->Find(chunk.incarnation());
    if (!worker) {
      return Reject("unregistered", absl::FailedPreconditionError(absl::StrCat(
                                        "unregistered incarnation ", chunk.incarnation(),
                                        ": call Register first")));
    }
    s_->registry->Touch(chunk.incarnation(), Clock::now());
    const int64_t current = s_->current_version();
    const int64_t lag = s_->run->service().synchronous() ? 0 : s_->run->service().max_policy_lag();
    if (chunk.policy_version() > current) {
      return Reject("unknown_version", absl::FailedPreconditionError(absl::StrCat(
                                           "chunk policy version ", chunk.policy_version(),
                                           " is newer than the learner's ", current)));
    }
    if (chunk.policy_version() < current - lag) {
      s_->metrics.Add("juggle_unrolls_dropped_total", chunk.num_unrolls(), {{"reason", "stale"}});
      return Reject("stale_version", absl::FailedPreconditionError(absl::StrCat(
                                         "chunk policy version ", chunk.policy_version(),
                                         " is more than ", lag, " behind the learner's ",
                                         current)));
    }
    if (chunk.unroll_length() != s_->run->ppo().unroll_length()) {
      return Reject("invalid", absl::InvalidArgumentError(absl::StrCat(
                                   "chunk unroll_length ", chunk.unroll_length(),
                                   " differs from the run's ", s_->run->ppo().unroll_length())));
    }
    absl::StatusOr<Contribution> decoded =
        DecodeChunk(chunk, s_->obs_dim, s_->act_dim, s_->num_nodes, s_->num_edges);
    if (!decoded.ok()) return Reject("invalid", decoded.status());
    ChunkPart part;
    part.slot = worker->slot;
    part.incarnation = chunk.incarnation();
    part.sequence = chunk.sequence();
    part.part = chunk.part();
    part.num_parts = chunk.num_parts();
    part.version = chunk.policy_version();
    part.data = std::move(*decoded);
    if (!s_->queue->Push(std::move(part), Clock::now() + std::chrono::seconds(30))) {
      return Reject("queue_full", absl::ResourceExhaustedError(
                                      "the learner's ingestion queue stayed full for 30 s"));
    }
    s_->metrics.Set("juggle_queue_depth", static_cast<double>(s_->queue->size()));
    return absl::OkStatus();
  }

  LearnerServer::State* s_;
};

absl::StatusOr<std::string> CompileModel(const LoadedConfig& config) {
  const std::string path = ModelFilePath(config);
  char error[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  if (m == nullptr) {
    return absl::InvalidArgumentError(absl::StrCat(config.env_locator.Where({{"model_file"}}),
                                                   ": cannot load MJCF '", path, "': ", error));
  }
  std::string bytes(mj_sizeModel(m), '\0');
  mj_saveModel(m, nullptr, bytes.data(), static_cast<int>(bytes.size()));
  mj_deleteModel(m);
  return bytes;
}

void DeclareMetrics(Metrics* m) {
  m->Declare("juggle_samples_total", "counter", "Environment steps trained on.");
  m->Declare("juggle_samples_per_second", "gauge", "Samples per second over the last iteration.");
  m->Declare("juggle_sim_seconds_per_second", "gauge", "Simulated seconds per wall second.");
  m->Declare("juggle_queue_depth", "gauge", "Chunks waiting in the ingestion queue.");
  m->Declare("juggle_policy_lag", "histogram", "Versions between an unroll's policy and the trained one.",
             {0, 1, 2, 3, 5, 10});
  m->Declare("juggle_chunks_rejected_total", "counter", "Chunks rejected, by reason.");
  m->Declare("juggle_unrolls_dropped_total", "counter", "Accepted unrolls never trained on, by reason.");
  m->Declare("juggle_policy_requests_rejected_total", "counter", "GetPolicy calls refused, by reason.");
  m->Declare("juggle_workers_connected", "gauge", "Live workers.");
  m->Declare("juggle_worker_heartbeat_age_seconds", "gauge", "Seconds since each worker's last sign of life.");
  m->Declare("juggle_worker_env_steps_per_second", "gauge", "Env steps per second reported by each worker.");
  m->Declare("juggle_worker_restarts_total", "counter", "Registrations that replaced a live slot.");
  m->Declare("juggle_worker_timeouts_total", "counter", "Workers forgotten after missing heartbeats.");
  m->Declare("juggle_policy_version", "gauge", "Current policy version.");
  m->Declare("juggle_iterations_total", "counter", "PPO iterations.");
  m->Declare("juggle_mean_return", "gauge", "Mean episode return over the last iteration.");
  m->Declare("juggle_completions_per_episode", "gauge", "Node completions per episode, last iteration.");
  m->Declare("juggle_episodes_total", "counter", "Episodes ended, by outcome.");
}

}  // namespace

LearnerServer::LearnerServer(std::unique_ptr<State> state) : state_(std::move(state)) {}
LearnerServer::~LearnerServer() { Shutdown(); }

absl::StatusOr<std::unique_ptr<LearnerServer>> LearnerServer::Start(LearnerOptions options) {
  auto s = std::make_unique<State>();
  s->options = std::move(options);
  const LoadedConfig& config = s->options.config;
  s->run = &config.run;
  const EnvDims dims = EnvDimsOf(config);
  s->num_nodes = dims.node_ids;
  s->num_edges = config.graph->num_edges();
  s->obs_dim = dims.obs;
  s->act_dim = dims.act;
  s->control_dt = ControlDt(config);
  ASSIGN_OR_RETURN(s->model_mjb, CompileModel(config));
  config::RunConfig for_workers = config.run;
  for_workers.clear_graph_file();
  google::protobuf::TextFormat::PrintToString(for_workers, &s->config_text);

  s->trainer = std::make_unique<PpoTrainer>(config.run.model(), config.run.ppo(), s->obs_dim,
                                            s->act_dim, config.run.seed());
  s->walk = std::make_unique<AdaptiveWalk>(config.graph.get());
  if (std::system(absl::StrCat("mkdir -p '", s->options.run_dir, "'").c_str()) != 0) {
    return absl::PermissionDeniedError(absl::StrCat("cannot create run directory ", s->options.run_dir));
  }
  s->checkpoints = std::make_unique<CheckpointDir>(s->options.run_dir + "/checkpoints",
                                                   std::max(1, config.run.service().keep_checkpoints()));
  if (!s->options.resume && !s->checkpoints->List().empty()) {
    // A fresh run must not mix its checkpoints with an older run's (resume and evaluation
    // take the newest file, which would be the older run's).
    return absl::FailedPreconditionError(absl::StrCat(
        "run directory ", s->options.run_dir, " already holds checkpoints (newest ",
        s->checkpoints->List().front(), "); pass --resume to continue that run, or choose "
        "another --run_dir"));
  }
  if (s->options.resume) {
    absl::StatusOr<CheckpointDir::Loaded> loaded = s->checkpoints->LoadLatest();
    if (!loaded.ok()) return loaded.status();
    for (const std::string& skipped : loaded->skipped) {
      std::fprintf(stderr, "warning: skipped unreadable checkpoint: %s\n", skipped.c_str());
    }
    RETURN_IF_ERROR(RestoreLearnerState(loaded->sections, s->trainer.get(), s->walk.get()));
    std::printf("resumed from %s at iteration %ld\n", loaded->path.c_str(),
                static_cast<long>(s->trainer->iteration()));
  }
  std::random_device entropy;  // incarnation ids only; never seeds training
  s->registry = std::make_unique<WorkerRegistry>(entropy());
  s->queue = std::make_unique<BoundedQueue<ChunkPart>>(std::max(1, config.run.service().queue_capacity()));
  DeclareMetrics(&s->metrics);
  s->PublishSnapshot();

  const int port = s->options.port >= 0 ? s->options.port : config.run.service().port();
  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  builder.AddListeningPort(
      absl::StrCat(s->options.listen_all_interfaces ? "0.0.0.0:" : "127.0.0.1:", port),
      grpc::InsecureServerCredentials(), &s->port);
  builder.SetMaxReceiveMessageSize(64 << 20);
  s->service = std::make_unique<RolloutServiceImpl>(s.get());
  builder.RegisterService(s->service.get());
  s->grpc_server = builder.BuildAndStart();
  if (!s->grpc_server || s->port == 0) {
    return absl::UnavailableError(absl::StrCat("learner: cannot listen on port ", port));
  }
  const int metrics_port =
      s->options.metrics_port >= 0 ? s->options.metrics_port : config.run.service().metrics_port();
  if (metrics_port > 0 || s->options.metrics_port == 0) {
    State* raw = s.get();
    ASSIGN_OR_RETURN(s->http, HttpServer::Start(
                                  metrics_port, s->options.listen_all_interfaces,
                                  [raw](const std::string& path) {
                                    if (path == "/metrics") return HttpResponse{200, "text/plain; version=0.0.4", raw->metrics.RenderPrometheus()};
                                    if (path == "/healthz") return HttpResponse{200, "text/plain", "ok\n"};
                                    return HttpResponse{404, "text/plain", "try /metrics\n"};
                                  }));
  }
  return std::unique_ptr<LearnerServer>(new LearnerServer(std::move(s)));
}

absl::Status LearnerServer::Train(const std::atomic<bool>* stop) {
  State& s = *state_;
  const config::ServiceConfig& svc = s.run->service();
  const int64_t max_iterations =
      s.options.max_iterations > 0 ? s.options.max_iterations : s.run->ppo().iterations();
  const auto start = Clock::now();
  ContributionAssembler assembler;
  std::vector<int> reported_slots;
  auto last_end = Clock::now();
  int64_t total_samples = 0;
  while (!stop->load()) {
    if (max_iterations > 0 && s.trainer->iteration() >= max_iterations) break;
    if (s.options.max_minutes > 0 &&
        std::chrono::duration<double>(Clock::now() - start).count() > s.options.max_minutes * 60) {
      break;
    }
    if (std::optional<ChunkPart> part = s.queue->Pop(Clock::now() + std::chrono::milliseconds(100))) {
      ++s.chunks_ingested;
      if (s.options.discard_data) continue;
      if (absl::Status added = assembler.Add(std::move(*part)); !added.ok()) {
        s.metrics.Add("juggle_chunks_rejected_total", 1, {{"reason", "inconsistent_parts"}});
        std::fprintf(stderr, "warning: %s\n", std::string(added.message()).c_str());
      }
    }
    s.metrics.Set("juggle_queue_depth", static_cast<double>(s.queue->size()));
    const auto now = Clock::now();
    for (uint64_t dead : s.registry->Expire(now, std::chrono::duration<double>(svc.worker_timeout_s()))) {
      s.metrics.Add("juggle_worker_timeouts_total", 1);
      std::printf("worker incarnation %lx timed out; its partial data is discarded\n",
                  static_cast<unsigned long>(dead));
    }
    const std::vector<WorkerInfo> live = s.registry->Live();
    std::vector<uint64_t> live_incarnations;
    std::vector<int> live_slots;
    int live_envs = 0;
    for (const WorkerInfo& w : live) {
      live_incarnations.push_back(w.incarnation);
      live_slots.push_back(w.slot);
      live_envs += w.num_envs;
      const std::string slot = absl::StrCat(w.slot);
      s.metrics.Set("juggle_worker_heartbeat_age_seconds",
                    std::chrono::duration<double>(now - w.last_seen).count(), {{"slot", slot}});
      s.metrics.Set("juggle_worker_env_steps_per_second", w.env_steps_per_s, {{"slot", slot}});
    }
    assembler.DropAllBut(live_incarnations);
    // Forget the per-slot series of workers that are gone.
    for (int slot : reported_slots) {
      if (std::find(live_slots.begin(), live_slots.end(), slot) == live_slots.end()) {
        s.metrics.Erase("juggle_worker_heartbeat_age_seconds", "slot", absl::StrCat(slot));
        s.metrics.Erase("juggle_worker_env_steps_per_second", "slot", absl::StrCat(slot));
      }
    }
    reported_slots = live_slots;
    s.metrics.Set("juggle_workers_connected", static_cast<double>(live.size()));

    const int64_t version = s.trainer->version();
    int64_t dropped = 0;
    std::optional<Contribution> batch;
    if (svc.synchronous()) {
      if (static_cast<int>(live.size()) >= std::max(1, svc.min_workers())) {
        batch = assembler.TakeSync(version, live_slots, &dropped);
      }
    } else {
      const int wanted = svc.unrolls_per_iteration() > 0 ? svc.unrolls_per_iteration() : live_envs;
      if (wanted > 0) batch = assembler.TakeAsync(version, svc.max_policy_lag(), wanted, &dropped);
    }
    if (dropped) s.metrics.Add("juggle_unrolls_dropped_total", dropped, {{"reason", "stale"}});
    if (!batch) continue;

    const auto t_update = Clock::now();
    for (const EdgeEvent& e : batch->events) s.walk->Apply(e).IgnoreError();
    double lag_sum = 0;
    for (int64_t v : batch->batch.policy_version) {
      s.metrics.Observe("juggle_policy_lag", static_cast<double>(version - v));
      lag_sum += version - v;
    }
    absl::StatusOr<UpdateStats> update =
        s.trainer->Update(batch->batch, svc.synchronous() ? 0 : svc.max_policy_lag());
    if (!update.ok()) {
      s.metrics.Add("juggle_unrolls_dropped_total", batch->batch.num_unrolls, {{"reason", "update"}});
      std::fprintf(stderr, "warning: batch rejected by the trainer: %s\n",
                   std::string(update.status().message()).c_str());
      continue;
    }
    s.PublishSnapshot();
    const auto t_end = Clock::now();

    IterationReport r;
    r.iteration = s.trainer->iteration();
    r.samples = batch->batch.num_samples();
    total_samples += r.samples;
    r.total_samples = total_samples;
    r.iteration_s = std::chrono::duration<double>(t_end - last_end).count();
    r.wait_s = std::chrono::duration<double>(t_update - last_end).count();
    r.update_s = std::chrono::duration<double>(t_end - t_update).count();
    r.samples_per_s = r.samples / std::max(r.iteration_s, 1e-9);
    r.sim_s_per_s = r.samples_per_s * s.control_dt;
    const EpisodeCounters& ep = batch->stats;
    r.episodes = ep.episodes;
    r.mean_return = ep.episodes ? ep.return_sum / ep.episodes : 0;
    r.mean_episode_len = ep.episodes ? double(ep.length_sum) / ep.episodes : 0;
    r.completions_per_episode = ep.episodes ? double(ep.completions_sum) / ep.episodes : 0;
    r.mean_policy_lag = batch->batch.num_unrolls ? lag_sum / batch->batch.num_unrolls : 0;
    r.workers = static_cast<int>(live.size());
    r.value_loss = update->value_loss;
    r.approx_kl = update->approx_kl;
    r.actor_lr = update->actor_lr;
    last_end = t_end;

    s.metrics.Add("juggle_samples_total", static_cast<double>(r.samples));
    s.metrics.Set("juggle_samples_per_second", r.samples_per_s);
    s.metrics.Set("juggle_sim_seconds_per_second", r.sim_s_per_s);
    s.metrics.Add("juggle_iterations_total", 1);
    s.metrics.Set("juggle_mean_return", r.mean_return);
    s.metrics.Set("juggle_completions_per_episode", r.completions_per_episode);
    for (size_t o = 0; o < ep.outcomes.size(); ++o) {
      if (ep.outcomes[o]) s.metrics.Add("juggle_episodes_total", static_cast<double>(ep.outcomes[o]), {{"outcome", OutcomeName(static_cast<Outcome>(o))}});
    }
    if (s.options.on_iteration) s.options.on_iteration(r);
    if (svc.checkpoint_every() > 0 && r.iteration % svc.checkpoint_every() == 0) {
      RETURN_IF_ERROR(s.Checkpoint());
    }
  }
  // No newer policy will come: release workers waiting for one (they get the current policy
  // at once instead of at their long poll's deadline, up to 30 s later).
  s.store.Close();
  return s.Checkpoint();
}

void LearnerServer::Shutdown() {
  if (!state_ || state_->shut_down) return;
  state_->shut_down = true;
  state_->store.Close();
  state_->queue->Close();
  if (state_->grpc_server) {
    state_->grpc_server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
    state_->grpc_server->Wait();
  }
  if (state_->http) state_->http->Stop();
}

int LearnerServer::port() const { return state_->port; }
int LearnerServer::metrics_port() const { return state_->http ? state_->http->port() : 0; }
int64_t LearnerServer::version() const { return state_->current_version(); }
int64_t LearnerServer::chunks_ingested() const { return state_->chunks_ingested.load(); }
const Metrics& LearnerServer::metrics() const { return state_->metrics; }

}  // namespace juggle
