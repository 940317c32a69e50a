#include "planner/tasks.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "envs/soccer_juggle/spec.h"
#include "planner/football/kick_task.h"
#include "planner/football/trap_kick_task.h"
#include "planner/football/trap_task.h"
#include "planner/soccer_juggle/task.h"
#include "planner/toss/task.h"

namespace juggle::planner {
namespace {

std::shared_ptr<const PlanningTask> MakeSoccerJuggleTask(std::shared_ptr<const EnvSpec> spec,
                                                         const config::PlannerConfig& config) {
  return std::make_shared<SoccerJuggleTask>(
      std::static_pointer_cast<const soccer_juggle::JuggleSpec>(std::move(spec)), config);
}

std::shared_ptr<const PlanningTask> MakeTossTask(std::shared_ptr<const EnvSpec> spec,
                                                 const config::PlannerConfig& config) {
  return std::make_shared<TossThrowTask>(
      std::static_pointer_cast<const toss::TossSpec>(std::move(spec)), config);
}

std::shared_ptr<const PlanningTask> MakeFootballTask(std::shared_ptr<const EnvSpec> spec,
                                                     const config::PlannerConfig& config) {
  auto football = std::static_pointer_cast<const football::FootballSpec>(std::move(spec));
  if (football->trap_kick()) {
    return std::make_shared<FootballTrapKickTask>(std::move(football), config);
  }
  if (football->trap()) return std::make_shared<FootballTrapTask>(std::move(football), config);
  return std::make_shared<FootballKickTask>(std::move(football), config);
}

}  // namespace

const std::vector<PlanningTaskEntry>& PlanningTasks() {
  static const auto* const kTasks = new std::vector<PlanningTaskEntry>{
      {"soccer_juggle", &ValidateSoccerJuggleTask, &MakeSoccerJuggleTask, /*refines=*/true,
       /*has_later_kicks=*/true, /*body_knots=*/true},
      {"toss", &ValidateTossTask, &MakeTossTask, /*refines=*/false,
       /*has_later_kicks=*/false, /*body_knots=*/false},
      // KICK and TRAP_KICK carry knots; TRAP refuses them itself (ValidateFootballTask).
      {"football", &ValidateFootballTask, &MakeFootballTask, /*refines=*/true,
       /*has_later_kicks=*/false, /*body_knots=*/true},
  };
  return *kTasks;
}

std::string FamiliesWithPlanningTasks() {
  std::vector<std::string> names;
  for (const PlanningTaskEntry& e : PlanningTasks()) names.push_back(e.family);
  return absl::StrJoin(names, ", ");
}

absl::StatusOr<const PlanningTaskEntry*> PlanningTaskFor(const std::string& family) {
  for (const PlanningTaskEntry& e : PlanningTasks()) {
    if (e.family == family) return &e;
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "the planner has no task for the ", family, " family; families with a planning task: ",
      FamiliesWithPlanningTasks(), " (docs/planner.md, \"Adding a planning task\")"));
}

absl::StatusOr<std::shared_ptr<const PlanningTask>> MakePlanningTask(
    std::shared_ptr<const EnvSpec> spec, const config::PlannerConfig& config) {
  absl::StatusOr<const PlanningTaskEntry*> entry = PlanningTaskFor(spec->family());
  if (!entry.ok()) return entry.status();
  return (*entry)->make(std::move(spec), config);
}

}  // namespace juggle::planner
