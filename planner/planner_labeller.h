// The planner as the worker's expert (envs/labeller.h): one receding-horizon planner per
// labelled env (planner/planner_set.h), all sharing one rollout pool of planner.threads
// threads and the family's planning task. Env k of worker w plans on random stream w·65536 + k, so labels are reproducible
// from (run seed, worker, env). Thread-compatible.
#ifndef JUGGLE_PLANNER_PLANNER_LABELLER_H_
#define JUGGLE_PLANNER_PLANNER_LABELLER_H_

#include "envs/labeller.h"

namespace juggle {

// The factory juggle-worker and local training hand to their workers. Errors: the planner's
// config check (ValidatePlannerConfig), a family the planner cannot drive.
absl::StatusOr<std::unique_ptr<Labeller>> MakePlannerLabeller(std::shared_ptr<const EnvSpec> spec,
                                                              const LoadedConfig& config,
                                                              int worker);

}  // namespace juggle

#endif  // JUGGLE_PLANNER_PLANNER_LABELLER_H_
