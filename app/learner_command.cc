// `juggle learner`: the learner process of a cluster run — gRPC rollout service, PPO training,
// checkpoints, /metrics. Workers are started elsewhere (`juggle-worker --learner=HOST:PORT`).
#include <cstdio>

#include "app/commands.h"
#include "app/connection_flags.h"
#include "app/learner_flags.h"
#include "app/security_flags.h"
#include "app/signals.h"
#include "learner/console_reporter.h"

namespace juggle {

CommandBody AddLearnerCommand(CLI::App* cmd) {
  struct Flags {
    LearnerFlags learner;
    SecurityFlags security;
    LearnerConnectionSettings connection;
    int port = -1;
    bool metrics_all_interfaces = false;
  };
  auto f = std::make_shared<Flags>();
  AddLearnerFlags(cmd, &f->learner);
  cmd->add_option("--port", f->port, "gRPC port (-1: the config's service.port; 0: any free)")
      ->check(Between(-1, 65535))
      ->capture_default_str();
  cmd->add_flag("--metrics_all_interfaces", f->metrics_all_interfaces,
                "serve /metrics and the dashboard on every interface (default: 127.0.0.1 only)");
  AddSecurityFlags(cmd, SecurityRole::kLearner, &f->security);
  AddLearnerConnectionFlags(cmd, &f->connection);
  return [f] {
    if (absl::Status s = Validate(f->connection); !s.ok()) return UsageError(std::string(s.message()));
    absl::StatusOr<LearnerOptions> options = MakeLearnerOptions(f->learner);
    if (!options.ok()) return Fail(options.status());
    absl::StatusOr<TransportSecurity> security = ResolveSecurity(f->security);
    if (!security.ok()) return Fail(security.status());
    options->port = f->port;
    options->http_all_interfaces = f->metrics_all_interfaces;
    options->security = *std::move(security);
    options->connection = f->connection;
    if (options->security.token.empty()) {
      std::fprintf(stderr,
                   "warning: no token (--token_file or $JUGGLE_TOKEN): anyone who reaches the "
                   "gRPC port can register and send training data (docs/reliability.md)\n");
    }
    const std::string run_dir = options->run_dir;
    ConsoleReporter console;  // a line per iteration and per evaluation
    options->observers.push_back(&console);
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
