#include "envs/planning_model.h"

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle {

absl::StatusOr<std::shared_ptr<const EnvSpec>> CreatePlanningSpec(
    const std::shared_ptr<const EnvSpec>& exact, const PlanningModelOptions& options) {
  const auto* juggle = dynamic_cast<const soccer_juggle::JuggleSpec*>(exact.get());
  if (juggle == nullptr) {
    return absl::UnimplementedError(absl::StrCat(
        "planner.planning_model: the ", exact->family(),
        " family has no planning model (only soccer_juggle has)"));
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const soccer_juggle::JuggleSpec> variant,
                   soccer_juggle::JuggleSpec::CreatePlanningVariant(*juggle, options));
  return std::shared_ptr<const EnvSpec>(std::move(variant));
}

}  // namespace juggle
