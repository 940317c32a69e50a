// `juggle bench planner`: what the planner's search costs. In one run: bare mj_step over the
// states the env visits (the physics alone), the planner driving its own episode on 1 and 2
// threads (restore, plan actions, the env's step, scoring and the search itself, counted in
// physics substeps of the rollouts, and wall seconds per simulated second), and the snapshot
// restore alone. Prints ratios; the last line is key=value pairs
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
#include "planner/planner_controller.h"
#include "planner/planning_pools.h"
#include "planner/rollout_pool.h"
#include "planner/receding_horizon.h"
#include "planner/tasks.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct SearchRate {
  double substeps_per_s = 0;      // physics substeps of the rollouts per wall second
  double seconds_per_replan = 0;
  double wall_s_per_sim_s = 0;    // what `juggle eval` reports for the planner
  int64_t rescues = 0;
  int64_t replans = 0;
};

// The planner driving its own episode (the start of stream (11, 0, 0); a new one if it ends)
// for `replans` × replan_every control steps on `threads` threads: what an evaluation spends, warm starts and
// rescues included. The planner's results do not depend on its threads, so every call visits
// the same states. `snapshots` (may be null) receives the state every 4th control step.
absl::StatusOr<SearchRate> PlannerEpisodeRate(std::shared_ptr<const JuggleSpec> spec,
                              const config::PlannerConfig& config, int replans, int threads,
                              std::vector<std::unique_ptr<EnvSnapshot>>* snapshots) {
  absl::StatusOr<planner::PlanningPools> pools = planner::MakePlanningPools(spec, config, threads);
  if (!pools.ok()) return pools.status();
  RolloutPool& pool = *pools->search;
  JuggleEnv env(spec, Rng::ForStream(11, 0, 0));
  AdaptiveWalk walk(&spec->graph());
  env.Reset(walk);
  absl::StatusOr<std::shared_ptr<const planner::PlanningTask>> task =
      planner::MakePlanningTask(spec, config);
  if (!task.ok()) return task.status();
  auto planner = std::make_unique<planner::RecedingHorizonPlanner>(*task, config, &pool, 0,
                                                                   nullptr, pools->exact.get());
  planner::PlannerTotals done;  // of the episodes that ended
  int64_t control_steps = 0;
  float action[kNumActions];
  const auto start = Clock::now();
  const int64_t steps_to_run = int64_t(replans) * config.replan_every();
  while (control_steps < steps_to_run) {
    if (snapshots != nullptr && control_steps % 4 == 0) snapshots->push_back(env.Snapshot());
    if (absl::Status s = planner->Act(env, action); !s.ok()) return s;
    ++control_steps;
    if (env.Step(action, walk).outcome != Outcome::kRunning) {
      done.replans += planner->totals().replans;
      done.rollout_steps += planner->totals().rollout_steps;
      done.rescues += planner->totals().rescues;
      env.Reset(walk);
      planner = std::make_unique<planner::RecedingHorizonPlanner>(
          *task, config, &pool, control_steps, nullptr, pools->exact.get());
    }
  }
  const double seconds = Seconds(start);
  const int64_t steps = done.rollout_steps + planner->totals().rollout_steps;
  const int64_t made = done.replans + planner->totals().replans;
  return SearchRate{double(steps) * spec->env().substeps() / seconds,
                    seconds / std::max<int64_t>(made, 1),
                    seconds / (control_steps * spec->control_dt()),
                    done.rescues + planner->totals().rescues, made};
}

}  // namespace

absl::Status RunPlannerBench(const PlannerBenchOptions& o) {
  if (o.replans < 1 || o.repeats < 1) {
    return absl::InvalidArgumentError("the planner bench needs at least 1 re-plan and 1 repeat");
  }
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  if (absl::Status s = planner::ApplyPlannerSettings(o.planner_set, &*config); !s.ok()) return s;
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = JuggleSpec::Create(*config);
  if (!spec.ok()) return spec.status();
  const config::PlannerConfig& planner = config->run.planner();
  const std::vector<VisitedState> states = RecordEnvStates(*spec, 400);
  std::printf("planner: %d samples x %d iterations, horizon %d steps; the planner's own episode "
              "for %d re-plans per measurement\n",
              planner.samples(), planner.iterations(), planner.horizon_steps(), o.replans);
  double mj = 0, restore_s = 1e9;
  SearchRate one, two;
  std::vector<std::unique_ptr<EnvSnapshot>> visited;
  JuggleEnv env(*spec, Rng(0));
  for (int r = 0; r < o.repeats; ++r) {  // interleaved, best of each
    mj = std::max(mj, BareMjStepRate(**spec, states));
    absl::StatusOr<SearchRate> a =
        PlannerEpisodeRate(*spec, planner, o.replans, 1, visited.empty() ? &visited : nullptr);
    if (!a.ok()) return a.status();
    absl::StatusOr<SearchRate> b = PlannerEpisodeRate(*spec, planner, o.replans, 2, nullptr);
    if (!b.ok()) return b.status();
    if (a->substeps_per_s > one.substeps_per_s) one = *a;
    if (b->substeps_per_s > two.substeps_per_s) two = *b;
    const auto start = Clock::now();
    constexpr int kRestores = 2000;
    for (int i = 0; i < kRestores; ++i) (void)env.Restore(*visited[i % visited.size()]);
    restore_s = std::min(restore_s, Seconds(start) / kRestores);
    std::printf("repeat %d: mj_step/s %.0f  rollout substeps/s 1 thread %.0f  2 threads %.0f  "
                "restore %.1f us\n",
                r + 1, mj, one.substeps_per_s, two.substeps_per_s, restore_s * 1e6);
    std::fflush(stdout);
  }
  // A rollout restores once per candidate: its share of a rollout's time.
  const double steps_per_rollout = planner.horizon_steps();
  const double rollout_s = steps_per_rollout * (*spec)->env().substeps() / one.substeps_per_s;
  std::printf("bare mj_step: %.0f substeps/s per core\n", mj);
  std::printf("planner rollouts, 1 thread: %.0f substeps/s (%.3f of bare mj_step), %.3f s per "
              "re-plan\n", one.substeps_per_s, one.substeps_per_s / mj, one.seconds_per_replan);
  std::printf("planner rollouts, 2 threads: %.0f substeps/s, %.3f s per re-plan = %.1f wall s "
              "per simulated s (%ld rescues in %ld re-plans)\n",
              two.substeps_per_s, two.seconds_per_replan, two.wall_s_per_sim_s,
              static_cast<long>(two.rescues), static_cast<long>(two.replans));
  std::printf("mjstep_per_s=%.0f rollout_substeps_per_s_t1=%.0f rollout_substeps_per_s_t2=%.0f "
              "rollout_over_mjstep=%.3f threads2_over_threads1=%.3f restore_us=%.1f "
              "restore_share=%.4f replan_s_t2=%.3f wall_s_per_sim_s_t1=%.2f "
              "wall_s_per_sim_s_t2=%.2f rescues=%ld\n",
              mj, one.substeps_per_s, two.substeps_per_s, one.substeps_per_s / mj,
              two.substeps_per_s / one.substeps_per_s, restore_s * 1e6,
              restore_s / (rollout_s + restore_s), two.seconds_per_replan, one.wall_s_per_sim_s,
              two.wall_s_per_sim_s, static_cast<long>(two.rescues));
  return absl::OkStatus();
}

}  // namespace juggle
