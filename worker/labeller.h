// The expert of planner-guided training as a worker sees it (docs/learning.md, "Planner-guided
// training"): the action it would take in an env's current state, in the policy's own action
// units. The worker links no planner; the app hands it a factory (app/labeller_factory.h).
// Thread-compatible: the collector calls it from one thread, between pool steps.
#ifndef JUGGLE_WORKER_LABELLER_H_
#define JUGGLE_WORKER_LABELLER_H_

#include <functional>
#include <memory>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"

namespace juggle {

class Labeller {
 public:
  virtual ~Labeller() = default;
  // Writes the expert's action (act_dim floats) for `env`'s current state. Called for every
  // step of the env in order (the expert may keep a plan between calls; a new episode shows as
  // the env's step count going back).
  virtual absl::Status Label(const Env& env, float* action) = 0;
};

// Builds the labeller of a run (its config's planner settings) for envs of `spec` on the
// worker of slot `worker` (its random streams derive from the run seed, the worker and the env).
using LabellerFactory = std::function<absl::StatusOr<std::unique_ptr<Labeller>>(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config, int worker)>;

// Which envs of a worker's pool the expert labels and which it drives (ImitationConfig).
struct LabelPlan {
  Labeller* labeller = nullptr;  // null: no labels
  int label_envs = 0;            // envs [0, label_envs) get a label every step
  int expert_envs = 0;           // of those, [0, expert_envs) act with the label (+ noise)
  double expert_noise = 0;       // std of the Gaussian noise on expert-driven actions
};

}  // namespace juggle

#endif  // JUGGLE_WORKER_LABELLER_H_
