// `juggle export-policy`: writes a checkpoint's policy (actor, log-std, observation
// normalizer, model config, sizes) as a binary ExportedPolicy: no trainer state, no libtorch
// needed to run it (common/eigen_policy.h PolicyFromExport). Toss in-loop training reads these
// as its frozen partners (TossLoopConfig.catch_policy_file / throw_policy_file).
#include <cstdio>
#include <fstream>
#include <string>

#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "learner/learner_state.h"

namespace juggle {

int RunExportPolicy(int argc, char** argv, int first) {
  const std::vector<FlagSpec> specs = {
      {"checkpoint", "", "checkpoint file or run directory (its newest checkpoint)"},
      {"out", "", "file to write (binary juggle.config.ExportedPolicy)"},
  };
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok() || flags->help() || flags->Get("checkpoint").empty() || flags->Get("out").empty()) {
    if (!flags.ok()) std::fprintf(stderr, "error: %s\n", std::string(flags.status().message()).c_str());
    std::printf("usage: juggle export-policy --checkpoint=PATH --out=FILE\n%s",
                Flags::Usage(specs).c_str());
    return flags.ok() && flags->help() ? 0 : 2;
  }
  auto fail = [](const absl::Status& s) {
    std::fprintf(stderr, "error: %s\n", std::string(s.message()).c_str());
    return 1;
  };
  absl::StatusOr<LoadedCheckpoint> checkpoint = LoadCheckpoint(flags->Get("checkpoint"));
  if (!checkpoint.ok()) return fail(checkpoint.status());
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(checkpoint->config_path);
  if (!config.ok()) return fail(config.status());
  absl::StatusOr<config::ExportedPolicy> exported =
      ExportPolicyFromCheckpoint(checkpoint->sections, *config);
  if (!exported.ok()) return fail(exported.status());
  exported->set_source(checkpoint->path);
  // Round trip before writing: the file must load where it is used.
  if (absl::StatusOr<EigenPolicy> p = PolicyFromExport(*exported); !p.ok()) return fail(p.status());
  const std::string out = flags->Get("out");
  std::ofstream file(out, std::ios::binary | std::ios::trunc);
  if (!file || !exported->SerializeToOstream(&file) || !file.flush()) {
    return fail(absl::PermissionDeniedError("cannot write " + out));
  }
  std::printf("exported %s (obs %d, actions %d, %zu bytes) to %s\n", checkpoint->path.c_str(),
              exported->obs_dim(), exported->act_dim(), exported->parameters().size(), out.c_str());
  return 0;
}

}  // namespace juggle
