// Where the policy-running commands (eval, render, toss, export-policy) get a policy: a
// checkpoint file (.jglc), a run directory (its newest readable checkpoint) or an exported
// policy (.jglpolicy, torch-free), each with the run config it was trained with — the copy
// stored with it (envs/stored_config.h), so that neither the working folder nor later edits of
// config, graph or model files change what loads. Files written before configs were stored load
// as before (their config and model read through the recorded config path) with a note.
#ifndef JUGGLE_APP_POLICY_SOURCE_H_
#define JUGGLE_APP_POLICY_SOURCE_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "envs/env.h"
#include "proto/policy.pb.h"

namespace juggle {

struct PolicySource {
  LoadedConfig config;                   // the config the policy runs under
  std::shared_ptr<const EnvSpec> spec;   // made from `config`
  std::shared_ptr<const EigenPolicy> policy;
  // The policy alone (parameters, sizes, model config, source), without a config.
  config::ExportedPolicy exported;
  std::string path;  // the file it was read from
  std::string note;  // "" or the line printed about an old-format file
};

// Loads `path`. `config_path`, if not empty, replaces the config stored with the policy (it
// must describe the same observation and action sizes). Prints `note`, if any, to stderr.
// Errors: NOT_FOUND / DATA_LOSS for unreadable files, FAILED_PRECONDITION when no config is
// known (pass --config), INVALID_ARGUMENT when the policy does not fit the config, and the
// config loaders' errors.
absl::StatusOr<PolicySource> LoadPolicySource(const std::string& path,
                                              const std::string& config_path);

// `source` as an exported policy of the newest format, its config stored in it (for
// WritePolicyFile).
config::ExportedPolicy ExportPolicySource(const PolicySource& source);

}  // namespace juggle

#endif  // JUGGLE_APP_POLICY_SOURCE_H_
