// The environment interface EnvPool and RolloutCollector run, whatever the family: soccer
// juggling (JuggleEnv) or toss juggling (TossEnv). EnvSpec holds what never changes during a
// run (the compiled model, sizes) and makes envs; worker/env_registry.h picks the family.
#ifndef JUGGLE_WORKER_ENV_H_
#define JUGGLE_WORKER_ENV_H_

#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "common/adaptive_walk.h"
#include "common/control_graph.h"
#include "common/outcome.h"
#include "common/rng.h"

namespace juggle {

struct StepResult {
  float reward = 0;
  Outcome outcome = Outcome::kRunning;
  // Ended without bootstrapping: every outcome but running and the time limit (a caught ball
  // and a release end toss episodes this way too).
  bool terminated() const { return outcome != Outcome::kRunning && outcome != Outcome::kTimeLimit; }
  bool truncated() const { return outcome == Outcome::kTimeLimit; }
};

// One environment. Thread-compatible: one thread at a time. Envs do not reset themselves.
class Env {
 public:
  virtual ~Env() = default;
  // Starts an episode; events are cleared.
  virtual void Reset(const AdaptiveWalk& walk) = 0;
  // Advances one control step. REQUIRES: `action` holds act_dim values (clamped to [−1, 1] by
  // the env) and the episode has not ended.
  virtual StepResult Step(const float* action, const AdaptiveWalk& walk) = 0;
  // REQUIRES: `obs` holds obs_dim floats.
  virtual void WriteObservation(float* obs) const = 0;
  // Edge events of the last step (empty for families without a control graph).
  virtual const std::vector<EdgeEvent>& events() const = 0;
  // Control steps of the current episode.
  virtual int steps() const = 0;
  // Node id the env is in (graph node; 0 for families without a graph).
  virtual int node() const = 0;
  // Successes of the current episode so far (nodes completed; toss: 1 after a catch or a
  // release).
  virtual int completions() const = 0;
  // Simulator state, for tests and tools. Mutating it is the caller's risk.
  virtual mjData* data() = 0;
};

class EnvSpec : public std::enable_shared_from_this<EnvSpec> {
 public:
  virtual ~EnvSpec() = default;
  virtual int obs_dim() const = 0;
  virtual int act_dim() const = 0;
  // The control graph the adaptive walk runs on (empty for families without one).
  virtual const ControlGraph& graph() const = 0;
  virtual const mjModel* model() const = 0;
  // A new env drawing from `rng`. REQUIRES: this spec is owned by a shared_ptr.
  virtual std::unique_ptr<Env> NewEnv(Rng rng) const = 0;
};

}  // namespace juggle

#endif  // JUGGLE_WORKER_ENV_H_
