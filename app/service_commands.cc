// `juggle learner`, `juggle worker` and `juggle train` (local mode): the rollout service's
// processes. Local mode runs the learner and its workers in this process over loopback gRPC —
// the same code path as a cluster.
#include <sys/stat.h>

#include <atomic>
#include <cstdlib>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "learner/checkpoint.h"
#include "learner/learner_server.h"
#include "learner/learner_state.h"
#include "worker/worker_client.h"

namespace juggle {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

void InstallSignalHandlers() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
}

int Fail(const absl::Status& s) {
  std::fprintf(stderr, "error: %s\n", std::string(s.message()).c_str());
  return 1;
}

std::string DefaultRunDir(const config::RunConfig& run) {
  return absl::StrCat("runs/", run.name().empty() ? "run" : run.name());
}

// Prints one progress line per iteration and appends it to <run_dir>/metrics.jsonl.
std::function<void(const IterationReport&)> ProgressReporter(const std::string& run_dir) {
  auto metrics = std::make_shared<std::ofstream>(run_dir + "/metrics.jsonl", std::ios::app);
  return [metrics](const IterationReport& r) {
    *metrics << r.ToJson() << "\n";
    metrics->flush();
    std::printf("%s\n", r.ToLine().c_str());
    std::fflush(stdout);
  };
}

// --init_from: a new run that starts from another run's checkpoint (fine-tuning under another
// config, e.g. toss in-loop training). The checkpoint is copied into <run_dir>/checkpoints,
// which must hold none yet; the run then resumes from it.
absl::Status SeedRunFromCheckpoint(const std::string& source, const std::string& run_dir) {
  CheckpointDir dir(run_dir + "/checkpoints");
  if (!dir.List().empty()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "--init_from: run directory ", run_dir, " already holds checkpoints (newest ",
        dir.List().front(), "); choose another --run_dir, or --resume without --init_from"));
  }
  absl::StatusOr<LoadedCheckpoint> checkpoint = LoadCheckpoint(source);
  if (!checkpoint.ok()) return checkpoint.status();
  const size_t slash = checkpoint->path.rfind('/');
  const std::string name =
      slash == std::string::npos ? checkpoint->path : checkpoint->path.substr(slash + 1);
  if (std::system(absl::StrCat("mkdir -p '", dir.dir(), "'").c_str()) != 0) {
    return absl::PermissionDeniedError(absl::StrCat("cannot create ", dir.dir()));
  }
  if (absl::Status s = WriteCheckpointFile(dir.dir() + "/" + name, checkpoint->sections); !s.ok()) {
    return s;
  }
  std::printf("starting from %s\n", checkpoint->path.c_str());
  return absl::OkStatus();
}

// Shared by `learner` and `train`: builds LearnerOptions from flags.
absl::StatusOr<LearnerOptions> LearnerOptionsFromFlags(const Flags& flags) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(flags.Get("config"));
  if (!config.ok()) return config.status();
  LearnerOptions o;
  o.run_dir = flags.Get("run_dir").empty() ? DefaultRunDir(config->run) : flags.Get("run_dir");
  o.config = std::move(*config);
  o.resume = flags.GetBool("resume");
  o.max_iterations = *flags.GetInt("iterations");
  o.max_minutes = *flags.GetDouble("minutes");
  ::mkdir("runs", 0755);
  if (::mkdir(o.run_dir.c_str(), 0755) != 0 && errno != EEXIST) {
    return absl::PermissionDeniedError(absl::StrCat("cannot create run directory ", o.run_dir));
  }
  if (!flags.Get("init_from").empty()) {
    if (o.resume) {
      return absl::InvalidArgumentError(
          "--init_from starts a new run; it cannot be combined with --resume");
    }
    if (absl::Status s = SeedRunFromCheckpoint(flags.Get("init_from"), o.run_dir); !s.ok()) {
      return s;
    }
    o.resume = true;  // from the copied checkpoint
  }
  o.on_iteration = ProgressReporter(o.run_dir);
  return o;
}

std::vector<FlagSpec> CommonLearnerFlags() {
  return {
      {"config", "configs/right_foot.textproto", "run config (protobuf text format)"},
      {"run_dir", "", "run directory: checkpoints/ and metrics.jsonl (default runs/<name>)"},
      {"resume", "false", "continue from the newest readable checkpoint in the run directory"},
      {"init_from", "", "start a new run from this checkpoint (file or run directory): "
                        "fine-tuning under this config"},
      {"iterations", "0", "stop after this many iterations (0: the config's ppo.iterations)"},
      {"minutes", "0", "stop after this many minutes (0: no limit)"},
  };
}

}  // namespace

int RunLearner(int argc, char** argv, int first) {
  std::vector<FlagSpec> specs = CommonLearnerFlags();
  specs.push_back({"port", "-1", "gRPC port (-1: the config's service.port)"});
  specs.push_back({"metrics_port", "-1", "HTTP /metrics port (-1: the config's; 0: any free)"});
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle learner --config=FILE [--port=N] [--metrics_port=N] [--resume]\n%s",
                Flags::Usage(specs).c_str());
    return 0;
  }
  absl::StatusOr<LearnerOptions> options = LearnerOptionsFromFlags(*flags);
  if (!options.ok()) return Fail(options.status());
  options->port = static_cast<int>(*flags->GetInt("port"));
  options->metrics_port = static_cast<int>(*flags->GetInt("metrics_port"));
  const std::string run_dir = options->run_dir;
  absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(std::move(*options));
  if (!server.ok()) return Fail(server.status());
  std::printf("learner: gRPC on port %d, metrics on port %d, run dir %s\n", (*server)->port(),
              (*server)->metrics_port(), run_dir.c_str());
  std::fflush(stdout);
  InstallSignalHandlers();
  const absl::Status status = (*server)->Train(&g_stop);
  (*server)->Shutdown();
  if (!status.ok()) return Fail(status);
  std::printf("learner: stopped at policy version %ld\n", static_cast<long>((*server)->version()));
  return 0;
}

int RunWorkerCommand(int argc, char** argv, int first) {
  const std::vector<FlagSpec> specs = {
      {"learner", "127.0.0.1:50051", "learner address host:port"},
      {"envs", "16", "environments in this worker"},
      {"threads", "2", "simulation threads"},
      {"slot", "-1", "worker slot (seeds its envs); -1 lets the learner choose"},
      {"give_up_after", "0", "exit after this many seconds without a learner (0: never)"},
  };
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle worker --learner=HOST:PORT [--envs=N --threads=T]\n%s",
                Flags::Usage(specs).c_str());
    return 0;
  }
  WorkerOptions o;
  o.learner_address = flags->Get("learner");
  o.num_envs = static_cast<int>(*flags->GetInt("envs"));
  o.num_threads = static_cast<int>(*flags->GetInt("threads"));
  o.requested_slot = static_cast<int>(*flags->GetInt("slot"));
  o.give_up_after_s = *flags->GetDouble("give_up_after");
  o.stop = &g_stop;
  InstallSignalHandlers();
  const absl::Status status = RunWorker(o);
  if (!status.ok()) return Fail(status);
  std::printf("worker: stopped\n");
  return 0;
}

int RunTrain(int argc, char** argv, int first) {
  std::vector<FlagSpec> specs = CommonLearnerFlags();
  specs.push_back({"workers", "0", "local workers (0: the config's service.local_workers)"});
  specs.push_back({"envs", "0", "envs per worker (0: the config's sampling.num_envs)"});
  specs.push_back({"threads", "0", "simulation threads per worker (0: the config's)"});
  specs.push_back({"metrics_port", "-1", "HTTP /metrics port (-1: the config's; 0: any free)"});
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle train [--config=FILE] [flags]\n%s", Flags::Usage(specs).c_str());
    return 0;
  }
  absl::StatusOr<LearnerOptions> options = LearnerOptionsFromFlags(*flags);
  if (!options.ok()) return Fail(options.status());
  const config::RunConfig run = options->config.run;
  options->port = 0;  // any free loopback port
  options->listen_all_interfaces = false;
  options->metrics_port = static_cast<int>(*flags->GetInt("metrics_port"));
  const int workers = *flags->GetInt("workers") > 0 ? static_cast<int>(*flags->GetInt("workers"))
                                                   : run.service().local_workers();
  const int envs = *flags->GetInt("envs") > 0 ? static_cast<int>(*flags->GetInt("envs"))
                                             : run.sampling().num_envs();
  const int threads = *flags->GetInt("threads") > 0 ? static_cast<int>(*flags->GetInt("threads"))
                                                   : run.sampling().num_threads();
  const std::string run_dir = options->run_dir;
  absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(std::move(*options));
  if (!server.ok()) return Fail(server.status());
  std::printf("training %s locally: %d worker(s) x %d envs x %d steps per iteration, run dir %s\n",
              run.name().c_str(), workers, envs, run.ppo().unroll_length(), run_dir.c_str());
  std::fflush(stdout);
  InstallSignalHandlers();
  std::atomic<bool> workers_stop{false};
  std::vector<std::thread> worker_threads;
  for (int w = 0; w < workers; ++w) {
    worker_threads.emplace_back([&, w] {
      WorkerOptions o;
      o.learner_address = absl::StrCat("127.0.0.1:", (*server)->port());
      o.num_envs = envs;
      o.num_threads = threads;
      o.requested_slot = w;
      o.stop = &workers_stop;
      o.verbose = false;
      const absl::Status s = RunWorker(o);
      if (!s.ok()) std::fprintf(stderr, "worker %d: %s\n", w, std::string(s.message()).c_str());
    });
  }
  const absl::Status status = (*server)->Train(&g_stop);
  workers_stop = true;
  for (std::thread& t : worker_threads) t.join();
  (*server)->Shutdown();
  if (!status.ok()) return Fail(status);
  std::printf("stopped at policy version %ld; checkpoints in %s/checkpoints\n",
              static_cast<long>((*server)->version()), run_dir.c_str());
  return 0;
}

}  // namespace juggle
