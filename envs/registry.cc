#include "envs/registry.h"

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/football/family.h"
#include "envs/soccer_juggle/family.h"
#include "envs/toss/family.h"

namespace juggle {

absl::Span<const EnvFamily* const> AllFamilies() {
  // Adding a family: one line here (docs/adding_an_env_family.md).
  static const EnvFamily* const kFamilies[] = {
      &soccer_juggle::Family(),
      &toss::Family(),
      &football::Family(),
  };
  return kFamilies;
}

absl::StatusOr<const EnvFamily*> FamilyOf(const config::RunConfig& run) {
  std::string choices;
  for (const EnvFamily* family : AllFamilies()) {
    if (family->config_case() == run.family_case()) return family;
    absl::StrAppend(&choices, choices.empty() ? "" : ", ", std::string(family->name()));
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "the config sets no environment family; set exactly one of: ", choices));
}

absl::StatusOr<LoadedConfig> ParseRunConfig(const std::string& text, const std::string& path) {
  ASSIGN_OR_RETURN(LoadedConfig loaded, ParseSharedRunConfig(text, path));
  absl::StatusOr<const EnvFamily*> family = FamilyOf(loaded.run);
  if (!family.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": ", family.status().message()));
  }
  RETURN_IF_ERROR((*family)->Prepare(&loaded));
  return loaded;
}

absl::StatusOr<LoadedConfig> LoadRunConfig(const std::string& path) {
  ASSIGN_OR_RETURN(std::string text, ReadConfigFile(path));
  return ParseRunConfig(text, path);
}

absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpec(const LoadedConfig& config) {
  return CreateEnvSpecFromCompiled(config, "");
}

absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateEnvSpecFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb) {
  ASSIGN_OR_RETURN(const EnvFamily* family, FamilyOf(config.run));
  return family->CreateSpec(config, model_mjb);
}

}  // namespace juggle
