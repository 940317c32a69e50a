// `juggle bench sim`: environment control steps per second on 1 and 2 threads and, in the same
// run, bare mj_step throughput of the same model from the same state. Prints ratios; the last
// line is key=value pairs (env_over_mjstep=, threads2_over_threads1=, ...).
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench/bench_clock.h"
#include "bench/benchmarks.h"
#include "bench/physics_reference.h"
#include "envs/mujoco_model.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/spec.h"
#include "worker/env_pool.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

using Clock = std::chrono::steady_clock;

// Env control steps per second with zero actions (automatic resets included).
double EnvStepRate(std::shared_ptr<const JuggleSpec> spec, int envs, int threads, int steps) {
  auto pool = EnvPool::Create(spec, envs, threads, /*seed=*/1);
  std::vector<float> actions(size_t(envs) * kNumActions, 0.0f);
  (*pool)->Reset();
  for (int i = 0; i < 10; ++i) (*pool)->Step(actions.data());  // warm up
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) (*pool)->Step(actions.data());
  return double(steps) * envs / SecondsSince(start);
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
