// `juggle bench planner`: what the planner's search costs. In one run: bare mj_step over the
// states the env visits (the physics alone), the planner's rollouts on 1 and 2 threads (restore,
// plan actions, the env's step, scoring and the search itself, counted in physics substeps of
// the rollouts), and the snapshot restore alone. Prints ratios; the last line is key=value pairs
// (rollout_over_mjstep=, threads2_over_threads1=, restore_share=, ...).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "bench/benchmarks.h"
#include "bench/physics_reference.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "planner/rollout_pool.h"
#include "planner/soccer_planner.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Snapshots of the states a zero-action env visits: every 4th control step, episodes restarted.
std::vector<std::unique_ptr<EnvSnapshot>> VisitedSnapshots(std::shared_ptr<const JuggleSpec> spec,
                                                          int count) {
  JuggleEnv env(spec, Rng(11));
  AdaptiveWalk walk(&spec->graph());
  env.Reset(walk);
  const float zero[kNumActions] = {0};
  std::vector<std::unique_ptr<EnvSnapshot>> out;
  for (int t = 0; static_cast<int>(out.size()) < count; ++t) {
    if (t % 4 == 0) out.push_back(env.Snapshot());
    if (env.Step(zero, walk).outcome != Outcome::kRunning) env.Reset(walk);
  }
  return out;
}

struct SearchRate {
  double substeps_per_s = 0;
  double seconds_per_replan = 0;
};

// One full re-plan from each snapshot, on `threads` threads.
SearchRate PlannerRate(std::shared_ptr<const JuggleSpec> spec, const config::PlannerConfig& config,
                       const std::vector<std::unique_ptr<EnvSnapshot>>& starts, int threads) {
  RolloutPool pool(spec, threads);
  JuggleEnv env(spec, Rng(0));
  int64_t steps = 0;
  const auto start = Clock::now();
  float action[kNumActions];
  for (size_t i = 0; i < starts.size(); ++i) {
    (void)env.Restore(*starts[i]);
    planner::SoccerPlanner planner(spec, config, &pool, i);
    (void)planner.Act(env, action);
    steps += planner.totals().rollout_steps;
  }
  const double seconds = Seconds(start);
  return {double(steps) * spec->env().substeps() / seconds, seconds / starts.size()};
}

}  // namespace

absl::Status RunPlannerBench(const PlannerBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = JuggleSpec::Create(*config);
  if (!spec.ok()) return spec.status();
  const config::PlannerConfig& planner = config->run.planner();
  const std::vector<std::unique_ptr<EnvSnapshot>> starts = VisitedSnapshots(*spec, o.replans);
  const std::vector<VisitedState> states = RecordEnvStates(*spec, 400);
  std::printf("planner: %d samples x %d iterations, horizon %d steps; %d re-plans from visited "
              "states per measurement\n",
              planner.samples(), planner.iterations(), planner.horizon_steps(), o.replans);
  double mj = 0, restore_s = 1e9;
  SearchRate one, two;
  JuggleEnv env(*spec, Rng(0));
  for (int r = 0; r < o.repeats; ++r) {  // interleaved, best of each
    mj = std::max(mj, BareMjStepRate(**spec, states));
    const SearchRate a = PlannerRate(*spec, planner, starts, 1);
    const SearchRate b = PlannerRate(*spec, planner, starts, 2);
    if (a.substeps_per_s > one.substeps_per_s) one = a;
    if (b.substeps_per_s > two.substeps_per_s) two = b;
    const auto start = Clock::now();
    constexpr int kRestores = 2000;
    for (int i = 0; i < kRestores; ++i) (void)env.Restore(*starts[i % starts.size()]);
    restore_s = std::min(restore_s, Seconds(start) / kRestores);
    std::printf("repeat %d: mj_step/s %.0f  rollout substeps/s 1 thread %.0f  2 threads %.0f  "
                "restore %.1f us\n",
                r + 1, mj, one.substeps_per_s, two.substeps_per_s, restore_s * 1e6);
    std::fflush(stdout);
  }
  // A rollout restores once per candidate: its share of a rollout's time.
  const double steps_per_rollout = planner.horizon_steps();
  const double rollout_s = steps_per_rollout * (*spec)->env().substeps() / one.substeps_per_s;
  const double sim_per_replan = planner.replan_every() * (*spec)->control_dt();
  std::printf("bare mj_step: %.0f substeps/s per core\n", mj);
  std::printf("planner rollouts, 1 thread: %.0f substeps/s (%.3f of bare mj_step), %.3f s per "
              "re-plan\n", one.substeps_per_s, one.substeps_per_s / mj, one.seconds_per_replan);
  std::printf("planner rollouts, 2 threads: %.0f substeps/s, %.3f s per re-plan = %.1f wall s "
              "per simulated s at a re-plan every %d steps\n",
              two.substeps_per_s, two.seconds_per_replan, two.seconds_per_replan / sim_per_replan,
              planner.replan_every());
  std::printf("mjstep_per_s=%.0f rollout_substeps_per_s_t1=%.0f rollout_substeps_per_s_t2=%.0f "
              "rollout_over_mjstep=%.3f threads2_over_threads1=%.3f restore_us=%.1f "
              "restore_share=%.4f replan_s_t2=%.3f wall_s_per_sim_s_t2=%.2f\n",
              mj, one.substeps_per_s, two.substeps_per_s, one.substeps_per_s / mj,
              two.substeps_per_s / one.substeps_per_s, restore_s * 1e6,
              restore_s / (rollout_s + restore_s), two.seconds_per_replan,
              two.seconds_per_replan / sim_per_replan);
  return absl::OkStatus();
}

}  // namespace juggle
