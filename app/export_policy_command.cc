// `juggle export-policy`: writes a checkpoint's policy (actor, log-std, observation
// normalizer, model config, sizes) and the run config it was trained with as a binary
// ExportedPolicy: no trainer state, no libtorch needed to run it (PolicyFromExport). `juggle
// eval`, `render` and `toss` run these files; toss in-loop training reads them as its frozen
// partners (TossLoopConfig.catch_policy_file / throw_policy_file).
#include <cstdio>

#include <string>

#include "app/commands.h"
#include "app/policy_source.h"
#include "common/file_io.h"

namespace juggle {

CommandBody AddExportPolicyCommand(CLI::App* cmd) {
  struct Flags {
    std::string checkpoint, out, config;
  };
  auto f = std::make_shared<Flags>();
  cmd->add_option("--checkpoint", f->checkpoint,
                  "checkpoint file or run directory (its newest checkpoint)")
      ->required();
  cmd->add_option("--out", f->out, "file to write (binary juggle.config.ExportedPolicy, "
                                   "conventionally .jglpolicy)")
      ->required();
  cmd->add_option("--config", f->config, "run config (default: the checkpoint's)");
  return [f] {
    absl::StatusOr<PolicySource> source = LoadPolicySource(f->checkpoint, f->config);
    if (!source.ok()) return Fail(source.status());
    if (absl::Status s = WriteFile(f->out, source->exported.SerializeAsString()); !s.ok()) {
      return Fail(s);
    }
    std::printf("exported %s (obs %d, actions %d, %zu bytes of parameters) to %s\n",
                source->path.c_str(), source->exported.obs_dim(), source->exported.act_dim(),
                source->exported.parameters().size(), f->out.c_str());
    return 0;
  };
}

}  // namespace juggle
