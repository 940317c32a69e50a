#include "app/policy_source.h"

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "google/protobuf/text_format.h"
#include "learner/learner_state.h"

namespace juggle {
namespace {

absl::StatusOr<config::ExportedPolicy> ReadExportedPolicy(const std::string& path) {
  ASSIGN_OR_RETURN(std::string bytes, ReadFile(path));
  config::ExportedPolicy exported;
  if (!exported.ParseFromString(bytes) || exported.parameters().empty()) {
    return absl::DataLossError(absl::StrCat(
        path, ": not an exported policy (write one with `juggle export-policy`)"));
  }
  return exported;
}

}  // namespace

absl::StatusOr<PolicySource> LoadPolicySource(const std::string& path,
                                              const std::string& config_path) {
  PolicySource out;
  out.path = path;
  if (absl::EndsWith(path, ".jglpolicy")) {
    ASSIGN_OR_RETURN(out.exported, ReadExportedPolicy(path));
    if (!config_path.empty()) {
      ASSIGN_OR_RETURN(out.config, LoadRunConfig(config_path));
    } else if (!out.exported.run_config().empty()) {
      ASSIGN_OR_RETURN(out.config,
                       ParseRunConfig(out.exported.run_config(), out.exported.config_path()));
    } else {
      return absl::FailedPreconditionError(absl::StrCat(
          path, " carries no run config (an older export): pass --config"));
    }
  } else {
    ASSIGN_OR_RETURN(LoadedCheckpoint checkpoint, LoadCheckpoint(path));
    out.path = checkpoint.path;
    const std::string config_file = config_path.empty() ? checkpoint.config_path : config_path;
    if (config_file.empty()) {
      return absl::FailedPreconditionError(absl::StrCat(
          checkpoint.path, " names no run config: pass --config"));
    }
    ASSIGN_OR_RETURN(out.config, LoadRunConfig(config_file));
    ASSIGN_OR_RETURN(std::shared_ptr<const EnvSpec> spec, CreateEnvSpec(out.config));
    ASSIGN_OR_RETURN(out.exported, ExportPolicyFromCheckpoint(checkpoint.sections, out.config,
                                                              spec->obs_dim(), spec->act_dim()));
    out.exported.set_source(checkpoint.path);
    std::string text;
    google::protobuf::TextFormat::PrintToString(out.config.run, &text);
    out.exported.set_run_config(text);
    out.exported.set_config_path(config_file);
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const EnvSpec> spec, CreateEnvSpec(out.config));
  if (out.exported.obs_dim() != spec->obs_dim() || out.exported.act_dim() != spec->act_dim()) {
    return absl::InvalidArgumentError(absl::StrCat(
        path, ": the policy has ", out.exported.obs_dim(), " observations and ",
        out.exported.act_dim(), " actions; ", out.config.config_path, " makes an env with ",
        spec->obs_dim(), " and ", spec->act_dim()));
  }
  ASSIGN_OR_RETURN(EigenPolicy policy, PolicyFromExport(out.exported));
  out.policy = std::make_shared<const EigenPolicy>(std::move(policy));
  return out;
}

}  // namespace juggle
