#include "bench/physics_reference.h"

#include <chrono>

#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/env.h"

namespace juggle {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

std::vector<VisitedState> RecordEnvStates(std::shared_ptr<const JuggleSpec> spec, int steps) {
  JuggleEnv env(spec, Rng(7));
  AdaptiveWalk walk(&spec->graph());
  env.Reset(walk);
  const mjModel* m = spec->model();
  const float zero[kNumActions] = {0};
  std::vector<VisitedState> states;
  for (int i = 0; i < steps; ++i) {
    const mjData* d = env.data();
    states.push_back({std::vector<double>(d->qpos, d->qpos + m->nq),
                      std::vector<double>(d->qvel, d->qvel + m->nv),
                      std::vector<double>(d->qfrc_applied, d->qfrc_applied + m->nv)});
    if (env.Step(zero, walk).outcome != Outcome::kRunning) env.Reset(walk);
  }
  return states;
}

double BareMjStepRate(const JuggleSpec& spec, const std::vector<VisitedState>& states) {
  const mjModel* m = spec.model();
  MjDataPtr data(mj_makeData(m));
  mjData* d = data.get();
  const int substeps = spec.env().substeps();
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  for (const VisitedState& s : states) {
    mju_copy(d->qpos, s.qpos.data(), m->nq);
    mju_copy(d->qvel, s.qvel.data(), m->nv);
    mju_copy(d->qfrc_applied, s.qfrc_applied.data(), m->nv);
    for (int k = 0; k < substeps; ++k) mj_step(m, d);
  }
  return double(states.size()) * substeps /
         std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace juggle
