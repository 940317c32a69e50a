#include "app/policy_source.h"

#include <cstdio>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "common/policy_file.h"
#include "common/status_macros.h"
#include "envs/policy_config.h"
#include "envs/registry.h"
#include "learner/learner_state.h"

namespace juggle {
namespace {

// Reads an exported policy and the config it runs under into `out`.
absl::Status LoadExported(const std::string& path, const std::string& config_path,
                          PolicySource* out) {
  if (!config_path.empty()) {
    ASSIGN_OR_RETURN(PolicyFile file, ReadPolicyFile(path));
    out->exported = std::move(file.policy);
    ASSIGN_OR_RETURN(out->config, LoadRunConfig(config_path));
  } else {
    ASSIGN_OR_RETURN(PolicyAndConfig loaded, LoadPolicyFile(path));
    out->exported = std::move(loaded.policy);
    out->config = std::move(loaded.config);
    out->note = std::move(loaded.note);
  }
  // The policy alone: the config travels in out->config.
  out->exported.clear_run_config();
  out->exported.clear_config_path();
  out->exported.clear_model_mjb();
  out->exported.clear_mujoco_version();
  return absl::OkStatus();
}

// Reads a checkpoint (file or run directory) and the config it runs under into `out`.
absl::Status LoadFromCheckpoint(const std::string& path, const std::string& config_path,
                                PolicySource* out) {
  ASSIGN_OR_RETURN(LoadedCheckpoint checkpoint, LoadCheckpoint(path));
  out->path = checkpoint.path;
  if (!config_path.empty()) {
    ASSIGN_OR_RETURN(out->config, LoadRunConfig(config_path));
  } else {
    ASSIGN_OR_RETURN(out->config, CheckpointConfig(checkpoint, &out->note));
  }
  ASSIGN_OR_RETURN(out->spec, CreateEnvSpec(out->config));
  ASSIGN_OR_RETURN(out->exported,
                   ExportPolicyFromCheckpoint(checkpoint.sections, out->config,
                                              out->spec->obs_dim(), out->spec->act_dim()));
  out->exported.set_source(checkpoint.path);
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<PolicySource> LoadPolicySource(const std::string& path,
                                              const std::string& config_path) {
  PolicySource out;
  out.path = path;
  if (absl::EndsWith(path, ".jglpolicy")) {
    RETURN_IF_ERROR(LoadExported(path, config_path, &out));
  } else {
    RETURN_IF_ERROR(LoadFromCheckpoint(path, config_path, &out));
  }
  if (!out.note.empty()) std::fprintf(stderr, "%s\n", out.note.c_str());
  if (out.spec == nullptr) {
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(out.config);
    if (!spec.ok()) {
      return absl::Status(spec.status().code(), absl::StrCat(path, ": ", spec.status().message()));
    }
    out.spec = *std::move(spec);
  }
  if (out.exported.obs_dim() != out.spec->obs_dim() ||
      out.exported.act_dim() != out.spec->act_dim()) {
    return absl::InvalidArgumentError(absl::StrCat(
        path, ": the policy has ", out.exported.obs_dim(), " observations and ",
        out.exported.act_dim(), " actions; ", out.config.config_path, " makes an env with ",
        out.spec->obs_dim(), " and ", out.spec->act_dim()));
  }
  ASSIGN_OR_RETURN(EigenPolicy policy, PolicyFromExport(out.exported));
  out.policy = std::make_shared<const EigenPolicy>(std::move(policy));
  return out;
}

config::ExportedPolicy ExportPolicySource(const PolicySource& source) {
  return WithStoredConfig(source.exported, source.config, *source.spec);
}

}  // namespace juggle
