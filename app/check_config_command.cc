// `juggle check-config`: loads a run config and builds its env spec (the model compiles and
// everything resolves against it); prints a summary or the first error.
#include <cstdio>

#include "app/commands.h"
#include "envs/registry.h"

namespace juggle {

CommandBody AddCheckConfigCommand(CLI::App* cmd) {
  auto path = std::make_shared<std::string>();
  cmd->add_option("--config,config", *path, "run config to check")->required();
  return [path] {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(*path);
    if (!config.ok()) return Fail(config.status());
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
    if (!spec.ok()) return Fail(spec.status());
    const ControlGraph& g = (*spec)->graph();
    std::printf("%s: OK\n  family %s, nodes %d, edges %d, initial %zu, obs %d, actions %d, "
                "control_dt %g s\n",
                config->config_path.c_str(), (*spec)->family().c_str(), g.num_nodes(),
                g.num_edges(), g.initial_nodes().size(), (*spec)->obs_dim(), (*spec)->act_dim(),
                (*spec)->control_dt());
    for (int n = 0; n < g.num_nodes(); ++n) {
      std::printf("  %-24s %-5s ->", g.node(n).name.c_str(),
                  config::Stage_Name(g.node(n).stage).c_str());
      for (int e : g.node(n).out_edges) {
        std::printf(" %s(%g)", g.node(g.edge(e).to).name.c_str(), g.edge(e).base_weight);
      }
      std::printf("\n");
    }
    return 0;
  };
}

}  // namespace juggle
