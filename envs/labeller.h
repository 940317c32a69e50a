// The expert of planner-guided training as a worker sees it (docs/learning.md, "Planner-guided
// training"): the action it would take in an env's current state, in the policy's own action
// units. Envs and workers know only this interface; the planner implements it
// (planner/planner_labeller.h) and the app hands workers its factory.
// Thread-compatible: the collector calls it from one thread, between pool steps.
#ifndef JUGGLE_ENVS_LABELLER_H_
#define JUGGLE_ENVS_LABELLER_H_

#include <functional>
#include <memory>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/expert_counters.h"
#include "common/eigen_policy.h"
#include "envs/env.h"

namespace juggle {

class Labeller {
 public:
  virtual ~Labeller() = default;
  // Writes the expert's action (act_dim floats) for `env`'s current state. Called for every
  // step of the env in order (the expert may keep a plan between calls; a new episode shows as
  // the env's step count going back).
  virtual absl::Status Label(const Env& env, float* action) = 0;
  // The policy acting in the envs of the Label calls that follow (null: none), until the next
  // call; the caller keeps it alive until then (worker/rollout_collector.cc sets it for each
  // unroll). A planner may use it as its proposal (PlannerConfig.policy_prior). Errors: a policy
  // the expert cannot use (e.g. of other sizes than its envs).
  virtual absl::Status SetPolicy(const EigenPolicy* policy) { return absl::OkStatus(); }
  // What the expert spent since the previous call (labels counted by the caller).
  virtual ExpertCounters TakeCounters() { return {}; }
};

// Builds the labeller of a run (its config's planner settings) for envs of `spec` on the
// worker of slot `worker` (its random streams derive from the run seed, the worker and the env).
using LabellerFactory = std::function<absl::StatusOr<std::unique_ptr<Labeller>>(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config, int worker)>;

}  // namespace juggle

#endif  // JUGGLE_ENVS_LABELLER_H_
