// `juggle learner`: the learner process of a cluster run — gRPC rollout service, PPO training,
// checkpoints, /metrics. Workers are started elsewhere (`juggle-worker --learner=HOST:PORT`).
#include <cstdio>

#include "app/commands.h"
#include "app/learner_flags.h"
#include "app/signals.h"

namespace juggle {

CommandBody AddLearnerCommand(CLI::App* cmd) {
  struct Flags {
    LearnerFlags learner;
    int port = -1;
  };
  auto f = std::make_shared<Flags>();
  AddLearnerFlags(cmd, &f->learner);
  cmd->add_option("--port", f->port, "gRPC port (-1: the config's service.port; 0: any free)")
      ->check(Between(-1, 65535))
      ->capture_default_str();
  return [f] {
    absl::StatusOr<LearnerOptions> options = MakeLearnerOptions(f->learner);
    if (!options.ok()) return Fail(options.status());
    options->port = f->port;
    const std::string run_dir = options->run_dir;
    absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(std::move(*options));
    if (!server.ok()) return Fail(server.status());
    std::printf("learner: gRPC on port %d, metrics on port %d, run dir %s\n", (*server)->port(),
                (*server)->metrics_port(), run_dir.c_str());
    std::fflush(stdout);
    const absl::Status status = (*server)->Train(InstallStopSignals());
    (*server)->Shutdown();
    if (!status.ok()) return Fail(status);
    std::printf("learner: stopped at policy version %ld\n", static_cast<long>((*server)->version()));
    return 0;
  };
}

}  // namespace juggle
