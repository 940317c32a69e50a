#include "worker/env_registry.h"

#include "common/env_family.h"
#include "worker/juggle_spec.h"
#include "worker/toss_spec.h"

namespace juggle {
namespace {

template <typename Spec>
absl::StatusOr<std::shared_ptr<const EnvSpec>> Upcast(
    absl::StatusOr<std::shared_ptr<const Spec>> spec) {
  if (!spec.ok()) return spec.status();
  return std::shared_ptr<const EnvSpec>(*std::move(spec));
}

}  // namespace

absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpec(const LoadedConfig& config) {
  switch (EnvFamilyOf(config.run)) {
    case EnvFamily::kToss: return Upcast(TossSpec::Create(config));
    case EnvFamily::kSoccer: break;
  }
  return Upcast(JuggleSpec::Create(config));
}

absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpecFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb) {
  switch (EnvFamilyOf(config.run)) {
    case EnvFamily::kToss: return Upcast(TossSpec::CreateFromCompiled(config, model_mjb));
    case EnvFamily::kSoccer: break;
  }
  return Upcast(JuggleSpec::CreateFromCompiled(config, model_mjb));
}

}  // namespace juggle
