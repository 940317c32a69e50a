// The run config an exported policy file carries (common/policy_file.h), as a LoadedConfig;
// storing a config into a policy for export; and one loader for the places that accept either a
// run config or a policy (a recording's header, --config of replay and export-bvh).
#ifndef JUGGLE_ENVS_POLICY_CONFIG_H_
#define JUGGLE_ENVS_POLICY_CONFIG_H_

#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "proto/policy.pb.h"

namespace juggle {

struct PolicyAndConfig {
  config::ExportedPolicy policy;
  LoadedConfig config;  // policy_file is the policy's path
  int format = 0;       // of the file (common/policy_file.h)
  std::string note;     // one line for stderr about an old-format file; "" for format 2
};

// Reads the policy file `path` and its run config. Format 2: the stored config and model
// (envs/stored_config.h; reads no other file). Format 1: the config text it carries, whose
// model_file is compiled relative to the recorded config_path, as before format 2 (so only from
// the folder it was exported in), and a note saying so. Errors name `path`: ReadPolicyFile's;
// FAILED_PRECONDITION for a format-1 file without a run config or a format-2 model written by
// another MuJoCo version (both: pass --config); LoadStoredConfig's / ParseRunConfig's.
absl::StatusOr<PolicyAndConfig> LoadPolicyFile(const std::string& path);

// `policy` (parameters, sizes, model config, source) with `config` stored in it — its text, its
// path and the compiled model of `spec` — ready for WritePolicyFile.
// REQUIRES: `spec` was made from `config`.
config::ExportedPolicy WithStoredConfig(config::ExportedPolicy policy, const LoadedConfig& config,
                                        const EnvSpec& spec);

// A path ending in ".jglpolicy": LoadPolicyFile's config, its note (if any) in `*note`; else
// LoadRunConfig. Errors as theirs.
absl::StatusOr<LoadedConfig> LoadConfigOrPolicy(const std::string& path, std::string* note);

}  // namespace juggle

#endif  // JUGGLE_ENVS_POLICY_CONFIG_H_
