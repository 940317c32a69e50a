// `juggle train` (local mode): the learner and its workers in this process over loopback gRPC —
// the same code path as a cluster.
#include <atomic>
#include <cstdio>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/learner_flags.h"
#include "planner/planner_labeller.h"
#include "app/signals.h"
#include "learner/console_reporter.h"
#include "worker/worker_client.h"

namespace juggle {

CommandBody AddTrainCommand(CLI::App* cmd) {
  struct Flags {
    LearnerFlags learner;
    int workers = 0, envs = 0, threads = 0;
  };
  auto f = std::make_shared<Flags>();
  AddLearnerFlags(cmd, &f->learner);
  cmd->add_option("--workers", f->workers, "local workers (0: the config's service.local_workers)")
      ->check(Between(0, 256))
      ->capture_default_str();
  cmd->add_option("--envs", f->envs, "envs per worker (0: the config's sampling.num_envs)")
      ->check(Between(0, 100000))
      ->capture_default_str();
  cmd->add_option("--threads", f->threads, "simulation threads per worker (0: the config's)")
      ->check(Between(0, 1024))
      ->capture_default_str();
  return [f] {
    absl::StatusOr<LearnerOptions> options = MakeLearnerOptions(f->learner);
    if (!options.ok()) return Fail(options.status());
    const config::RunConfig run = options->config.run;
    options->port = 0;  // any free loopback port
    options->listen_all_interfaces = false;
    // The dashboard on a free loopback port unless a port (or 0: off) is given.
    if (f->learner.metrics_port == -1 && !run.service().has_metrics_port()) {
      options->metrics_port = LearnerOptions::kAnyFreePort;
    }
    const int workers = f->workers > 0 ? f->workers : run.service().local_workers();
    const int envs = f->envs > 0 ? f->envs : run.sampling().num_envs();
    const int threads = f->threads > 0 ? f->threads : run.sampling().num_threads();
    const std::string run_dir = options->run_dir;
    ConsoleReporter console;  // a line per iteration and per evaluation
    options->observers.push_back(&console);
    absl::StatusOr<std::unique_ptr<LearnerServer>> server =
        LearnerServer::Start(std::move(*options));
    if (!server.ok()) return Fail(server.status());
    std::printf("training %s locally: %d worker(s) x %d envs x %d steps per iteration, run dir %s\n",
                run.name().c_str(), workers, envs, run.ppo().unroll_length(), run_dir.c_str());
    if ((*server)->metrics_port() > 0) {
      std::printf("dashboard: http://127.0.0.1:%d/\n", (*server)->metrics_port());
    }
    std::fflush(stdout);
    std::atomic<bool>* stop = InstallStopSignals();
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
        o.labeller_factory = MakePlannerLabeller;
        const absl::Status s = RunWorker(o);
        if (!s.ok()) {
          std::fprintf(stderr, "worker %d: %s\n", w, std::string(s.message()).c_str());
          *stop = true;  // a local worker that cannot run makes the run pointless
        }
      });
    }
    const absl::Status status = (*server)->Train(stop);
    workers_stop = true;
    for (std::thread& t : worker_threads) t.join();
    (*server)->Shutdown();
    if (!status.ok()) return Fail(status);
    std::printf("stopped at policy version %ld; checkpoints in %s/checkpoints\n",
                static_cast<long>((*server)->version()), run_dir.c_str());
    return 0;
  };
}

}  // namespace juggle
