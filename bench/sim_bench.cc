// `juggle bench sim`: environment control steps per second on 1 and 2 threads and, in the same
// run, bare mj_step throughput of the same model from the same state. Prints ratios; the last
// line is key=value pairs (env_over_mjstep=, threads2_over_threads1=, ...).
#include <chrono>
#include <cstdio>
#include <vector>

#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "worker/env_pool.h"
#include "worker/juggle_env.h"
#include "worker/juggle_spec.h"

namespace juggle {
namespace {

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
  mjData* d = mj_makeData(m);
  const int substeps = spec.env().substeps();
  const auto start = Clock::now();
  for (const VisitedState& s : states) {
    mju_copy(d->qpos, s.qpos.data(), m->nq);
    mju_copy(d->qvel, s.qvel.data(), m->nv);
    mju_copy(d->qfrc_applied, s.qfrc_applied.data(), m->nv);
    for (int k = 0; k < substeps; ++k) mj_step(m, d);
  }
  const double rate = double(states.size()) * substeps / Seconds(start);
  mj_deleteData(d);
  return rate;
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

int RunBenchSim(int argc, char** argv, int first) {
  const std::vector<FlagSpec> specs = {
      {"config", "configs/right_foot.textproto", "run config"},
      {"envs", "32", "envs in the pool"},
      {"steps", "300", "batch steps per measurement"},
      {"repeats", "3", "alternating repeats of every measurement (best is reported)"},
  };
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok() || flags->help()) {
    if (!flags.ok()) std::fprintf(stderr, "error: %s\n", std::string(flags.status().message()).c_str());
    std::printf("usage: juggle bench sim [flags]\n%s", Flags::Usage(specs).c_str());
    return flags.ok() ? 0 : 2;
  }
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(flags->Get("config"));
  if (!config.ok()) {
    std::fprintf(stderr, "error: %s\n", std::string(config.status().message()).c_str());
    return 1;
  }
  auto spec = JuggleSpec::Create(*config);
  if (!spec.ok()) {
    std::fprintf(stderr, "error: %s\n", std::string(spec.status().message()).c_str());
    return 1;
  }
  const int envs = static_cast<int>(*flags->GetInt("envs"));
  const int steps = static_cast<int>(*flags->GetInt("steps"));
  const int repeats = static_cast<int>(*flags->GetInt("repeats"));
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
  return 0;
}

}  // namespace juggle
