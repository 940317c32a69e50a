// `juggle export-policy`: writes a policy (actor, log-std, observation normalizer, model config,
// sizes) without its trainer, with the run config it was trained with stored in it — the text
// with every file inlined and the compiled MuJoCo model — as a policy file of the newest format
// (common/policy_file.h): no libtorch and no other file needed to run it (PolicyFromExport,
// envs/policy_config.h). The source is a checkpoint, a run directory, or an exported policy:
// exporting an older .jglpolicy again upgrades it (its model compiled from the MJCF its config
// names, so run that from the folder it was exported in). `juggle eval`, `render` and `toss`
// run these files; toss in-loop training reads them as its frozen partners
// (TossLoopConfig.catch_policy_file / throw_policy_file).
#include <cstdio>

#include <string>

#include "app/commands.h"
#include "app/policy_source.h"
#include "common/policy_file.h"

namespace juggle {

CommandBody AddExportPolicyCommand(CLI::App* cmd) {
  struct Flags {
    std::string checkpoint, out, config;
  };
  auto f = std::make_shared<Flags>();
  cmd->add_option("--checkpoint,--policy", f->checkpoint,
                  "checkpoint file, run directory (its newest checkpoint) or exported policy "
                  "(.jglpolicy: written again in the newest format)")
      ->required();
  cmd->add_option("--out", f->out, "file to write (policy file of format 2, conventionally "
                                   ".jglpolicy)")
      ->required();
  cmd->add_option("--config", f->config, "run config (default: the one stored with the source)");
  return [f] {
    absl::StatusOr<PolicySource> source = LoadPolicySource(f->checkpoint, f->config);
    if (!source.ok()) return Fail(source.status());
    const config::ExportedPolicy exported = ExportPolicySource(*source);
    if (absl::Status s = WritePolicyFile(f->out, exported); !s.ok()) return Fail(s);
    std::printf("exported %s (obs %d, actions %d, %zu bytes of parameters, %zu bytes of "
                "compiled model, config %s) to %s\n",
                source->path.c_str(), exported.obs_dim(), exported.act_dim(),
                exported.parameters().size(), exported.model_mjb().size(),
                exported.config_path().c_str(), f->out.c_str());
    return 0;
  };
}

}  // namespace juggle
