// `juggle worker` (and the `juggle-worker` binary): a simulation worker of a cluster run. Links
// worker/ only: no libtorch, no GL.
#include <cstdio>

#include "app/command.h"
#include "app/commands.h"
#include "app/connection_flags.h"
#include "planner/planner_labeller.h"
#include "app/security_flags.h"
#include "app/signals.h"
#include "worker/health_probe.h"
#include "worker/worker_client.h"

namespace juggle {

CommandBody AddWorkerCommand(CLI::App* cmd) {
  auto o = std::make_shared<WorkerOptions>();
  auto security = std::make_shared<SecurityFlags>();
  o->learner_address = "127.0.0.1:50051";
  cmd->add_option("--learner", o->learner_address, "learner address host:port")
      ->capture_default_str();
  cmd->add_option("--envs", o->num_envs, "environments in this worker")
      ->check(Between(1, 100000))
      ->capture_default_str();
  cmd->add_option("--threads", o->num_threads, "simulation threads")
      ->check(Between(1, 1024))
      ->capture_default_str();
  cmd->add_option("--slot", o->requested_slot,
                  "worker slot (seeds its envs); -1 lets the learner choose")
      ->check(AtLeast(-1))
      ->capture_default_str();
  cmd->add_option("--give_up_after", o->give_up_after_s,
                  "exit after this many seconds without a learner (0: never)")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--max_chunks_in_flight", o->max_chunks_in_flight,
                  "trajectory chunks sent to the learner and not yet acknowledged, at most (1: "
                  "wait for each chunk's ack before sending the next; more hides the round trip)")
      ->check(Between(1, kMaxChunksInFlightLimit))
      ->capture_default_str();
  auto probe = std::make_shared<bool>(false);
  cmd->add_flag("--probe", *probe,
                "check the learner's gRPC health service once (with these security flags) and "
                "exit: 0 if it is SERVING, 1 if not (for container probes)");
  AddSecurityFlags(cmd, SecurityRole::kWorker, security.get());
  AddWorkerConnectionFlags(cmd, &o->connection);
  return [o, security, probe] {
    if (absl::Status s = Validate(o->connection); !s.ok()) return UsageError(std::string(s.message()));
    absl::StatusOr<TransportSecurity> resolved = ResolveSecurity(*security);
    if (!resolved.ok()) return Fail(resolved.status());
    o->security = *std::move(resolved);
    if (*probe) {
      const absl::Status health = ProbeLearnerHealth(o->learner_address, o->security, 5.0);
      if (!health.ok()) return Fail(health);
      std::printf("learner at %s: SERVING\n", o->learner_address.c_str());
      return 0;
    }
    o->stop = InstallStopSignals();
    o->labeller_factory = MakePlannerLabeller;
    const absl::Status status = RunWorker(*o);
    if (!status.ok()) return Fail(status);
    std::printf("worker: stopped\n");
    return 0;
  };
}

}  // namespace juggle
