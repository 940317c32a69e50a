// juggle: train physically simulated characters to juggle a soccer ball.
#include <cstdio>
#include <cstring>
#include <string>

#include "app/commands.h"

namespace {

void PrintUsage() {
  std::printf(
      "usage: juggle <command> [flags]   (juggle <command> --help for its flags)\n\n"
      "commands:\n"
      "  train         train locally: a learner and its workers in one process over loopback\n"
      "  learner       the learner process of a cluster run (gRPC, /metrics, checkpoints)\n"
      "  worker        a simulation worker of a cluster run\n"
      "  eval          evaluate a checkpoint (mean action) or the zero-action baseline\n"
      "  simulate      run an env pool with zero or random actions and report episode stats\n"
      "  check-config  load and validate a run config and its model; print a summary\n"
      "  render        render a rollout to MP4/PNG (+ contact sheet); record and replay\n"
      "  siteswap      toss-juggling siteswaps: validity, state, throw schedule, transitions\n"
      "  toss          juggle a siteswap with trained catch/throw policies; --eval: the protocol\n"
      "  export-policy write a checkpoint's policy without its trainer (toss in-loop partners)\n"
      "  bench sim     env steps/s on 1 and 2 threads vs bare mj_step, in one run\n"
      "  bench moe     layer-wise vs weight-blended MoE, PPO update and Eigen inference speed\n"
      "  bench ingest  unrolls/s one learner ingests from synthetic workers over loopback\n"
      "  bench broadcast  snapshot broadcast time to 32 connected workers\n"
      "  bench local   local-mode iteration time vs sampling alone + update alone\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  if (command == "train") return juggle::RunTrain(argc, argv, 2);
  if (command == "eval") return juggle::RunEval(argc, argv, 2);
  if (command == "learner") return juggle::RunLearner(argc, argv, 2);
  if (command == "worker") return juggle::RunWorkerCommand(argc, argv, 2);
  if (command == "simulate") return juggle::RunSimulate(argc, argv, 2);
  if (command == "check-config") return juggle::RunCheckConfig(argc, argv, 2);
  if (command == "render") return juggle::RunRender(argc, argv, 2);
  if (command == "siteswap") return juggle::RunSiteswap(argc, argv, 2);
  if (command == "toss") return juggle::RunToss(argc, argv, 2);
  if (command == "export-policy") return juggle::RunExportPolicy(argc, argv, 2);
  if (command == "bench") {
    if (argc >= 3 && std::string(argv[2]) == "sim") return juggle::RunBenchSim(argc, argv, 3);
    const std::string name = argc >= 3 ? argv[2] : "";
    if (name == "moe") return juggle::RunBenchMoe(argc, argv, 3);
    if (name == "ingest") return juggle::RunBenchIngest(argc, argv, 3);
    if (name == "broadcast") return juggle::RunBenchBroadcast(argc, argv, 3);
    if (name == "local") return juggle::RunBenchLocal(argc, argv, 3);
    std::fprintf(stderr, "juggle bench: expected a benchmark: sim | moe | ingest | broadcast | local\n");
    return 2;
  }
  std::fprintf(stderr, "juggle: unknown command '%s'\n\n", command.c_str());
  PrintUsage();
  return 2;
}
