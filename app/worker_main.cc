// juggle-worker: the worker alone, for cluster jobs that run hundreds of them. Links worker/,
// envs/, common/, gRPC and MuJoCo — no libtorch, no GL (tests/worker_binary_test.sh checks).
#include "app/command.h"
#include "app/commands.h"

int main(int argc, char** argv) {
  CLI::App app("juggle-worker: a simulation worker of a juggle cluster run (docs/cluster.md)",
               "juggle-worker");
  const juggle::CommandBody body = juggle::AddWorkerCommand(&app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (see juggle-worker --help)\n", e.what());
    return juggle::kExitUsage;
  }
  return body();
}
