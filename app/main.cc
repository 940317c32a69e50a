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
      "  train         run the main job for a config (today: simulation with zero actions;\n"
      "                the PPO learner arrives with the learner issue)\n"
      "  simulate      run an env pool with zero or random actions and report episode stats\n"
      "  check-config  load and validate a run config and its model; print a summary\n"
      "  bench sim     env steps/s on 1 and 2 threads vs bare mj_step, in one run\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  if (command == "train") return juggle::RunSimulate(argc, argv, 2, /*as_train=*/true);
  if (command == "simulate") return juggle::RunSimulate(argc, argv, 2, /*as_train=*/false);
  if (command == "check-config") return juggle::RunCheckConfig(argc, argv, 2);
  if (command == "bench") {
    if (argc >= 3 && std::string(argv[2]) == "sim") return juggle::RunBenchSim(argc, argv, 3);
    std::fprintf(stderr, "juggle bench: expected a benchmark name: sim\n");
    return 2;
  }
  std::fprintf(stderr, "juggle: unknown command '%s'\n\n", command.c_str());
  PrintUsage();
  return 2;
}
