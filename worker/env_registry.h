// The workers' registry of environment families: builds the EnvSpec a RunConfig selects
// (common/env_family.h). One explicit switch, no static self-registration.
#ifndef JUGGLE_WORKER_ENV_REGISTRY_H_
#define JUGGLE_WORKER_ENV_REGISTRY_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "worker/env.h"

namespace juggle {

// Compiles the family's MJCF. Errors name the config field or the MJCF problem.
absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpec(const LoadedConfig& config);
// From the compiled model the learner ships (mj_saveModel bytes).
absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpecFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb);

}  // namespace juggle

#endif  // JUGGLE_WORKER_ENV_REGISTRY_H_
