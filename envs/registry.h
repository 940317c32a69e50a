// THE list of environment families (envs/registry.cc: one line per family, no static
// self-registration), and the functions every process uses to load a run config and build its
// environments through that list.
#ifndef JUGGLE_ENVS_REGISTRY_H_
#define JUGGLE_ENVS_REGISTRY_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/types/span.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "envs/env_family.h"

namespace juggle {

// Every family, in the order of envs/registry.cc.
absl::Span<const EnvFamily* const> AllFamilies();

// The family `run` selects. INVALID_ARGUMENT naming the choices when none is set.
absl::StatusOr<const EnvFamily*> FamilyOf(const config::RunConfig& run);

// Reads, parses and validates a RunConfig file: the shared sections, then the family's own
// (EnvFamily::Prepare). Errors: NOT_FOUND (missing file), INVALID_ARGUMENT (syntax, unknown
// fields, semantic checks), each message starting with "file:line:col".
absl::StatusOr<LoadedConfig> LoadRunConfig(const std::string& path);
// As LoadRunConfig, from text; `path` names the text in messages and anchors relative paths.
absl::StatusOr<LoadedConfig> ParseRunConfig(const std::string& text, const std::string& path);

// The family's EnvSpec for a loaded config: compiles its MJCF (or loads config.model_mjb, the
// model a stored config carries: envs/stored_config.h). Errors name the config field or
// the MJCF problem.
absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpec(const LoadedConfig& config);
// From the compiled model the learner ships (mj_saveModel bytes).
absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpecFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb);

}  // namespace juggle

#endif  // JUGGLE_ENVS_REGISTRY_H_
