// `juggle bench sim`: environment control steps per second on 1 and 2 threads and, in the same
// run, bare mj_step throughput of the same model from the same state. Prints ratios; the last
// line is key=value pairs (env_over_mjstep=, threads2_over_threads1=, ...).
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench/benchmarks.h"
#include "envs/registry.h"
#include "worker/env_pool.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A state the env visited at the start of a control step, with the torques it applied.
struct VisitedState {
  std::vector<double> qpos, qvel, qfrc_applied;
};

// Records the states one env visits over `steps` zero-action control steps (with resets).
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

// Bare mj_step calls per second over the same states: each recorded control step is replayed
// as `substeps` mj_steps from its state with its torques held — the physics of the env's own
// trajectory without any of the env's code.
double BareMjStepRate(const JuggleSpec& spec, const std::vector<VisitedState>& states) {
  const mjModel* m = spec.model();
  MjDataPtr data(mj_makeData(m));
  mjData* d = data.get();
  const int substeps = spec.env().substeps();
  const auto start = Clock::now();
  for (const VisitedState& s : states) {
    mju_copy(d->qpos, s.qpos.data(), m->nq);
    mju_copy(d->qvel, s.qvel.data(), m->nv);
    mju_copy(d->qfrc_applied, s.qfrc_applied.data(), m->nv);
    for (int k = 0; k < substeps; ++k) mj_step(m, d);
  }
  return double(states.size()) * substeps / Seconds(start);
}

// Env control steps per second with zero actions (automatic resets included).
double EnvStepRate(std::shared_ptr<const JuggleSpec> spec, int envs, int threads, int steps) {
  auto pool = EnvPool::Create(spec, envs, threads, /*seed=*/1);
  std::vector<float> actions(size_t(envs) * kNumActions, 0.0f);
  (*pool)->Reset();
  for (int i = 0; i < 10; ++i) (*pool)->Step(actions.data());  // warm up
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) (*pool)->Step(actions.data());
  return double(steps) * envs / Seconds(start);
}

}  // namespace

absl::Status RunSimBench(const SimBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  auto spec = JuggleSpec::Create(*config);
  if (!spec.ok()) return spec.status();
  const int envs = o.envs, steps = o.steps, repeats = o.repeats;
  const int substeps = (*spec)->env().substeps();

  const std::vector<VisitedState> states = RecordEnvStates(*spec, steps * envs / 4);
  double mj = 0, env1 = 0, env2 = 0;
  for (int r = 0; r < repeats; ++r) {  // interleave so machine noise hits all three alike
    mj = std::max(mj, BareMjStepRate(**spec, states));
    env1 = std::max(env1, EnvStepRate(*spec, envs, 1, steps));
    env2 = std::max(env2, EnvStepRate(*spec, envs, 2, steps));
    std::printf("repeat %d: mj_step/s %.0f  env steps/s 1 thread %.0f  2 threads %.0f\n", r + 1,
                mj, env1, env2);
    std::fflush(stdout);
  }
  const double control_dt = (*spec)->control_dt();
  std::printf("bare mj_step: %.0f steps/s = %.1f simulated s/s per core\n", mj,
              mj * (*spec)->env().sim_dt());
  std::printf("env, 1 thread: %.0f control steps/s = %.1f simulated s/s\n", env1,
              env1 * control_dt);
  std::printf("env, 2 threads: %.0f control steps/s = %.1f simulated s/s\n", env2,
              env2 * control_dt);
  std::printf("mjstep_per_s=%.0f env_steps_per_s_t1=%.0f env_steps_per_s_t2=%.0f "
              "sim_s_per_s_t1=%.1f sim_s_per_s_t2=%.1f env_over_mjstep=%.3f "
              "threads2_over_threads1=%.3f\n",
              mj, env1, env2, env1 * control_dt, env2 * control_dt, env1 * substeps / mj,
              env2 / env1);
  return absl::OkStatus();
}

}  // namespace juggle
