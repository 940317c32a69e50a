#include "learner/learner_server.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>

#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>

#include "absl/strings/str_cat.h"
#include "common/adaptive_walk.h"
#include "common/bounded_queue.h"
#include "common/file_io.h"
#include "common/http_server.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "envs/stored_config.h"
#include "learner/checkpoint.h"
#include "learner/contribution_assembler.h"
#include "learner/demo_buffer.h"
#include "learner/dashboard_state.h"
#include "learner/http_routes.h"
#include "learner/in_run_eval.h"
#include "learner/learner_metrics.h"
#include "learner/learner_state.h"
#include "learner/policy_store.h"
#include "learner/ppo_trainer.h"
#include "learner/rollout_service.h"
#include "learner/run_log.h"
#include "learner/training_loop.h"
#include "learner/worker_registry.h"

namespace juggle {

struct LearnerServer::State {
  LearnerOptions options;
  std::shared_ptr<const EnvSpec> spec;
  WorkerBootstrap bootstrap;
  std::unique_ptr<PpoTrainer> trainer;
  std::unique_ptr<AdaptiveWalk> walk;
  std::unique_ptr<DemoBuffer> demos;  // planner-guided training only
  RunProgress progress;
  std::unique_ptr<WorkerRegistry> registry;
  std::unique_ptr<BoundedQueue<ChunkPart>> queue;
  PolicyStore store;
  BroadcastTracker broadcast;
  Metrics metrics;
  std::unique_ptr<CheckpointDir> checkpoints;
  std::unique_ptr<RolloutService> service;
  std::unique_ptr<grpc::Server> grpc_server;
  std::unique_ptr<HttpServer> http;
  std::unique_ptr<InRunEvaluator> evaluator;
  std::unique_ptr<DashboardState> dashboard;
  std::unique_ptr<RunLogWriter> run_log;
  std::unique_ptr<LearnerMetrics> metrics_observer;
  int port = 0;
  bool shut_down = false;
  std::atomic<int64_t> chunks_ingested{0};

  void PublishSnapshot() {
    auto snap = std::make_shared<PolicySnapshot>();
    snap->version = trainer->version();
    snap->params = trainer->ExportPolicy().Serialize();
    snap->edge_counts = walk->counts();
    std::vector<uint64_t> live;
    if (registry) {
      for (const WorkerInfo& w : registry->Live()) live.push_back(w.incarnation);
    }
    broadcast.Published(snap->version, std::chrono::steady_clock::now(), live);
    store.Publish(std::move(snap));
    metrics.Set("juggle_policy_version", static_cast<double>(trainer->version()));
  }
  absl::StatusOr<std::string> Checkpoint() {
    absl::StatusOr<std::string> path =
        checkpoints->Save(trainer->iteration(),
                          SaveLearnerState(bootstrap.config, options.config.config_path,
                                           *trainer, *walk, progress));
    if (path.ok() && demos) {
      // One copy beside the checkpoints, replaced whole: a resumed run keeps its labels.
      RETURN_IF_ERROR(WriteFileAtomically(DemosPath(), demos->Serialize()));
    }
    return path;
  }
  std::string DemosPath() const { return options.run_dir + "/demos.jgld"; }
};

namespace {

// The spec, the bootstrap every worker receives, and the trainer's sizes.
absl::Status BuildEnv(const LoadedConfig& config,
                      std::shared_ptr<const EnvSpec>* spec, WorkerBootstrap* b) {
  absl::StatusOr<std::shared_ptr<const EnvSpec>> built = CreateEnvSpec(config);
  if (!built.ok()) {
    return absl::Status(built.status().code(),
                        absl::StrCat("the run config does not make an environment: ",
                                     built.status().message()));
  }
  *spec = *std::move(built);
  const config::RunConfig& run = config.run;
  b->config = StoreConfig(config, **spec);
  b->synchronous = run.service().synchronous();
  b->max_policy_lag = b->synchronous ? 0 : run.service().max_policy_lag();
  b->unroll_length = run.ppo().unroll_length();
  b->obs_dim = (*spec)->obs_dim();
  b->act_dim = (*spec)->act_dim();
  // Samples carry a node id: graph nodes, or 0 for families without a graph.
  b->num_nodes = std::max(1, (*spec)->graph().num_nodes());
  b->num_edges = (*spec)->graph().num_edges();
  return absl::OkStatus();
}

// imitation.initial_demos_file into `demos` (a run without a saved buffer of its own).
absl::Status SeedDemos(const LoadedConfig& config, DemoBuffer* demos) {
  const std::string path = ResolvePath(config.config_dir, config.run.imitation().initial_demos_file());
  auto refuse = [&](const absl::Status& s) {
    return absl::Status(s.code(), absl::StrCat("imitation.initial_demos_file: ", path, ": ",
                                               s.message()));
  };
  absl::StatusOr<std::string> bytes = ReadFile(path);  // its errors name the path
  if (!bytes.ok()) {
    return absl::Status(bytes.status().code(),
                        absl::StrCat("imitation.initial_demos_file: ", bytes.status().message()));
  }
  absl::StatusOr<DemoBuffer> saved = DemoBuffer::Parse(*bytes);
  if (!saved.ok()) return refuse(saved.status());
  absl::StatusOr<int64_t> added = demos->AddAll(*saved);
  if (!added.ok()) return refuse(added.status());
  std::printf("the demonstration buffer starts with %ld demonstrations from %s\n",
              static_cast<long>(demos->size()), path.c_str());
  if (demos->size() < config.run.imitation().min_buffer()) {
    std::fprintf(stderr, "warning: %ld demonstrations are fewer than imitation.min_buffer (%d): "
                 "no cloning or imitation term until labelling envs add more\n",
                 static_cast<long>(demos->size()), config.run.imitation().min_buffer());
  }
  return absl::OkStatus();
}

}  // namespace

LearnerServer::LearnerServer(std::unique_ptr<State> state) : state_(std::move(state)) {}
LearnerServer::~LearnerServer() { Shutdown(); }

absl::StatusOr<std::unique_ptr<LearnerServer>> LearnerServer::Start(LearnerOptions options) {
  auto s = std::make_unique<State>();
  s->options = std::move(options);
  const LoadedConfig& config = s->options.config;
  RETURN_IF_ERROR(BuildEnv(config, &s->spec, &s->bootstrap));

  s->trainer = std::make_unique<PpoTrainer>(config.run.model(), config.run.ppo(),
                                            s->bootstrap.obs_dim, s->bootstrap.act_dim,
                                            config.run.seed());
  s->walk = std::make_unique<AdaptiveWalk>(config.graph.get());
  const config::ImitationConfig& imitation = config.run.imitation();
  if (imitation.label_envs() > 0 || !imitation.initial_demos_file().empty()) {
    // Saved with every checkpoint (State::Checkpoint) and loaded on --resume below.
    s->demos = std::make_unique<DemoBuffer>(config.run.imitation().buffer_size(),
                                            s->bootstrap.obs_dim, s->bootstrap.act_dim);
  }
  std::error_code error;
  std::filesystem::create_directories(s->options.run_dir, error);
  if (error) {
    return absl::PermissionDeniedError(absl::StrCat("cannot create run directory ",
                                                    s->options.run_dir, ": ", error.message()));
  }
  s->checkpoints = std::make_unique<CheckpointDir>(
      s->options.run_dir + "/checkpoints", std::max(1, config.run.service().keep_checkpoints()));
  if (!s->options.resume && !s->checkpoints->List().empty()) {
    // A fresh run must not mix its checkpoints with an older run's (resume and evaluation
    // take the newest file, which would be the older run's).
    return absl::FailedPreconditionError(absl::StrCat(
        "run directory ", s->options.run_dir, " already holds checkpoints (newest ",
        s->checkpoints->List().front(), "); pass --resume to continue that run, or choose "
        "another --run_dir"));
  }
  if (s->options.resume) {
    ASSIGN_OR_RETURN(CheckpointDir::Loaded loaded, s->checkpoints->LoadLatest());
    for (const std::string& skipped : loaded.skipped) {
      std::fprintf(stderr, "warning: skipped unreadable checkpoint: %s\n", skipped.c_str());
    }
    RETURN_IF_ERROR(RestoreLearnerState(loaded.sections, s->trainer.get(), s->walk.get(),
                                        &s->progress));
    std::printf("resumed from %s at iteration %ld (%ld samples, %.0f s of training so far)\n",
                loaded.path.c_str(), static_cast<long>(s->trainer->iteration()),
                static_cast<long>(s->progress.samples), s->progress.train_seconds);
    if (s->demos && std::filesystem::exists(s->DemosPath())) {
      absl::StatusOr<std::string> bytes = ReadFile(s->DemosPath());
      absl::StatusOr<DemoBuffer> saved =
          bytes.ok() ? DemoBuffer::Parse(*bytes, s->demos->capacity(), s->demos->obs_dim(),
                                         s->demos->act_dim())
                     : absl::StatusOr<DemoBuffer>(bytes.status());
      if (saved.ok()) {
        *s->demos = *std::move(saved);
        std::printf("restored %ld demonstrations (of %ld labelled so far) from %s\n",
                    static_cast<long>(s->demos->size()), static_cast<long>(s->demos->added()),
                    s->DemosPath().c_str());
      } else {
        std::fprintf(stderr, "warning: %s not restored (%s); the buffer starts empty\n",
                     s->DemosPath().c_str(), std::string(saved.status().message()).c_str());
      }
    }
  }
  if (s->demos && !s->options.resume && !imitation.initial_demos_file().empty()) {
    RETURN_IF_ERROR(SeedDemos(config, s->demos.get()));
  }
  std::random_device entropy;  // incarnation ids only; never seeds training
  const config::ServiceConfig& service = config.run.service();
  RegistryLimits limits;
  limits.max_workers = service.max_workers();
  limits.max_workers_per_host = service.max_workers_per_host();
  limits.max_envs_per_worker = service.max_envs_per_worker();
  s->registry = std::make_unique<WorkerRegistry>(entropy(), limits);
  s->queue = std::make_unique<BoundedQueue<ChunkPart>>(
      std::max(1, config.run.service().queue_capacity()));
  ASSIGN_OR_RETURN(s->evaluator, InRunEvaluator::Create(config));
  s->dashboard = std::make_unique<DashboardState>(DescribeRun(config, *s->spec));
  s->dashboard->SetInitial(s->walk->counts(), s->trainer->version(), s->progress.samples,
                           s->progress.train_seconds);
  DeclareLearnerMetrics(&s->metrics);
  {
    const DashboardRunInfo& info = s->dashboard->info();
    s->metrics.Set("juggle_run_info", 1,
                   {{"config", info.config_name},
                    {"family", info.family},
                    {"mode", info.synchronous ? "synchronous" : "asynchronous"}});
    s->metrics.Set("juggle_learner_start_time_seconds", UnixNow());
    s->metrics.Set("juggle_ingest_queue_capacity_chunks", info.queue_capacity);
    s->metrics.Set("juggle_ingest_queue_chunks", 0);
    s->metrics.Set("juggle_workers_connected", 0);
    s->metrics.Set("juggle_workers_needed",
                   info.synchronous ? std::max(1, info.min_workers) : 1);
    s->metrics.Set("juggle_iterations_total", 0);
    s->metrics.Set("juggle_samples_total", 0);
  }
  ASSIGN_OR_RETURN(s->run_log, RunLogWriter::Open(RunLogPath(s->options.run_dir),
                                                  RunRecordOf(s->dashboard->info(), UnixNow())));
  std::vector<std::pair<std::string, std::string>> edge_labels;
  for (const DashboardRunInfo::Edge& e : s->dashboard->info().edges) {
    edge_labels.emplace_back(s->dashboard->info().nodes[e.from].name,
                             s->dashboard->info().nodes[e.to].name);
  }
  s->metrics_observer = std::make_unique<LearnerMetrics>(&s->metrics, std::move(edge_labels));
  s->PublishSnapshot();

  // gRPC.
  const int port = s->options.port >= 0 ? s->options.port : config.run.service().port();
  grpc::EnableDefaultHealthCheckService(true);
  ASSIGN_OR_RETURN(std::shared_ptr<grpc::ServerCredentials> credentials,
                   MakeServerCredentials(s->options.security));
  RETURN_IF_ERROR(Validate(s->options.connection));
  grpc::ServerBuilder builder;
  ApplyTo(s->options.connection, &builder);
  builder.AddListeningPort(
      absl::StrCat(s->options.listen_all_interfaces ? "0.0.0.0:" : "127.0.0.1:", port),
      credentials, &s->port);
  builder.SetMaxReceiveMessageSize(service.max_chunk_mb() << 20);
  s->service = std::make_unique<RolloutService>(
      RolloutService::Deps{s->registry.get(), &s->store, s->queue.get(), &s->metrics,
                           &s->bootstrap, s->options.security.token,
                           /*max_concurrent_calls=*/2 * service.max_workers() + 16,
                           &s->broadcast});
  builder.RegisterService(s->service.get());
  s->grpc_server = builder.BuildAndStart();
  if (!s->grpc_server || s->port == 0) {
    return absl::UnavailableError(absl::StrCat("learner: cannot listen on port ", port));
  }
  // HTTP: -1 the config's port (0 = off), 0 off, kAnyFreePort any free port.
  const int metrics_port = s->options.metrics_port == -1 ? config.run.service().metrics_port()
                                                           : s->options.metrics_port;
  if (metrics_port > 0 || metrics_port == LearnerOptions::kAnyFreePort) {
    ASSIGN_OR_RETURN(s->http, HttpServer::Start(std::max(0, metrics_port),
                                                s->options.http_all_interfaces,
                                                LearnerHttpRoutes(&s->metrics, s->dashboard.get(),
                                                                  s->registry.get())));
  }
  return std::unique_ptr<LearnerServer>(new LearnerServer(std::move(s)));
}

absl::Status LearnerServer::Train(const std::atomic<bool>* stop) {
  State& s = *state_;
  const config::RunConfig& run = s.options.config.run;
  TrainingLoop::Deps deps;
  deps.service = &run.service();
  deps.trainer = s.trainer.get();
  deps.walk = s.walk.get();
  deps.registry = s.registry.get();
  deps.queue = s.queue.get();
  deps.metrics = &s.metrics;
  deps.progress = &s.progress;
  deps.chunks_ingested = &s.chunks_ingested;
  deps.control_dt = s.spec->control_dt();
  deps.outcome_names = s.spec->outcome_names();
  deps.publish_snapshot = [&s] { s.PublishSnapshot(); };
  deps.release_workers = [&s] { s.store.Close(); };
  deps.checkpoint = [&s] { return s.Checkpoint(); };
  deps.evaluator = s.evaluator.get();
  deps.model = &run.model();
  deps.obs_dim = s.bootstrap.obs_dim;
  deps.act_dim = s.bootstrap.act_dim;
  deps.discard_data = s.options.discard_data;
  deps.imitation = &run.imitation();
  deps.demos = s.demos.get();
  deps.observers = {s.run_log.get(), s.metrics_observer.get(), s.dashboard.get()};
  deps.observers.insert(deps.observers.end(), s.options.observers.begin(),
                        s.options.observers.end());
  TrainingLoop::Limits limits;
  limits.max_iterations =
      s.options.max_iterations > 0 ? s.options.max_iterations : run.ppo().iterations();
  limits.max_minutes = s.options.max_minutes;
  return TrainingLoop(std::move(deps), limits).Run(stop);
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
int64_t LearnerServer::version() const { return state_->store.Current()->version; }
int64_t LearnerServer::chunks_ingested() const { return state_->chunks_ingested.load(); }
const Metrics& LearnerServer::metrics() const { return state_->metrics; }

}  // namespace juggle
