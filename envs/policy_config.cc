#include "envs/policy_config.h"

#include <mujoco/mujoco.h>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "common/policy_file.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "envs/stored_config.h"

namespace juggle {

absl::StatusOr<PolicyAndConfig> LoadPolicyFile(const std::string& path) {
  ASSIGN_OR_RETURN(PolicyFile file, ReadPolicyFile(path));
  PolicyAndConfig out;
  out.format = file.format;
  out.policy = std::move(file.policy);
  const config::ExportedPolicy& p = out.policy;
  if (file.format == 1) {
    if (p.run_config().empty()) {
      return absl::FailedPreconditionError(absl::StrCat(
          path, " carries no run config (an older export): pass --config"));
    }
    // As before format 2: the text names its model relative to the config it was read from.
    ASSIGN_OR_RETURN(out.config, ParseRunConfig(p.run_config(), p.config_path()));
    out.note = absl::StrCat(
        "note: ", path, " is an old-format policy that names its model relative to ",
        p.config_path(), " (so it loads only from the folder it was exported in); re-export it "
        "to make it self-contained: juggle export-policy --checkpoint=", path, " --out=NEW");
  } else {
    if (p.mujoco_version() != mj_version()) {
      return absl::FailedPreconditionError(absl::StrCat(
          path, ": its model was compiled by MuJoCo version ", p.mujoco_version(),
          " and this build has ", mj_version(), ", which may not read it: pass --config=",
          p.config_path(), " (or the config it was trained with) to compile the MJCF again"));
    }
    ASSIGN_OR_RETURN(out.config,
                     LoadStoredConfig({p.run_config(), p.model_mjb()},
                                      absl::StrCat(path, " (stored run config)"), p.config_path()));
  }
  out.config.policy_file = path;
  return out;
}

config::ExportedPolicy WithStoredConfig(config::ExportedPolicy policy, const LoadedConfig& config,
                                        const EnvSpec& spec) {
  StoredConfig stored = StoreConfig(config, spec);
  policy.set_run_config(std::move(stored.text));
  policy.set_model_mjb(std::move(stored.model_mjb));
  policy.set_mujoco_version(mj_version());
  policy.set_config_path(config.config_path);
  return policy;
}

absl::StatusOr<LoadedConfig> LoadConfigOrPolicy(const std::string& path, std::string* note) {
  if (!absl::EndsWith(path, ".jglpolicy")) return LoadRunConfig(path);
  ASSIGN_OR_RETURN(PolicyAndConfig loaded, LoadPolicyFile(path));
  if (note != nullptr) *note = loaded.note;
  return std::move(loaded.config);
}

}  // namespace juggle
