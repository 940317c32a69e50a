// `juggle check-config`: loads a run config and its model, prints a summary or the first error.
#include <cstdio>

#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "common/env_family.h"
#include "worker/env_registry.h"

namespace juggle {

int RunCheckConfig(int argc, char** argv, int first) {
  const std::vector<FlagSpec> specs = {{"config", "", "run config to check"}};
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok() || flags->help() || flags->Get("config").empty()) {
    if (!flags.ok()) std::fprintf(stderr, "error: %s\n", std::string(flags.status().message()).c_str());
    std::printf("usage: juggle check-config --config=FILE\n%s", Flags::Usage(specs).c_str());
    return flags.ok() && flags->help() ? 0 : 2;
  }
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(flags->Get("config"));
  if (!config.ok()) {
    std::fprintf(stderr, "error: %s\n", std::string(config.status().message()).c_str());
    return 1;
  }
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) {
    std::fprintf(stderr, "error: %s\n", std::string(spec.status().message()).c_str());
    return 1;
  }
  const ControlGraph& g = (*spec)->graph();
  std::printf("%s: OK\n  family %s, nodes %d, edges %d, initial %zu, obs %d, actions %d\n",
              config->config_path.c_str(), EnvFamilyName(EnvFamilyOf(config->run)), g.num_nodes(),
              g.num_edges(), g.initial_nodes().size(), (*spec)->obs_dim(), (*spec)->act_dim());
  for (int n = 0; n < g.num_nodes(); ++n) {
    std::printf("  %-24s %-5s ->", g.node(n).name.c_str(),
                config::Stage_Name(g.node(n).stage).c_str());
    for (int e : g.node(n).out_edges) {
      std::printf(" %s(%g)", g.node(g.edge(e).to).name.c_str(), g.edge(e).base_weight);
    }
    std::printf("\n");
  }
  return 0;
}

}  // namespace juggle
