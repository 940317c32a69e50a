// The bare-physics reference of the simulation benchmarks: the states an env visits, replayed
// as plain mj_step calls (the same model, the same states and torques, none of the env's code).
#ifndef JUGGLE_BENCH_PHYSICS_REFERENCE_H_
#define JUGGLE_BENCH_PHYSICS_REFERENCE_H_

#include <memory>
#include <vector>

#include "envs/soccer_juggle/spec.h"

namespace juggle {

// A state the env visited at the start of a control step, with the torques it applied.
struct VisitedState {
  std::vector<double> qpos, qvel, qfrc_applied;
};

// Records the states one env visits over `steps` zero-action control steps (with resets).
std::vector<VisitedState> RecordEnvStates(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                                          int steps);

// Bare mj_step calls per second over `states`: each recorded control step is replayed as
// `substeps` mj_steps from its state with its torques held.
double BareMjStepRate(const soccer_juggle::JuggleSpec& spec,
                      const std::vector<VisitedState>& states);

}  // namespace juggle

#endif  // JUGGLE_BENCH_PHYSICS_REFERENCE_H_
