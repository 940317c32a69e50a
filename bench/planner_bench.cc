// `juggle bench planner`: what the planner's search costs. In one run: bare mj_step over the
// states the env visits (the physics alone), the planner driving its own episode on 1 and 2
// threads (restore, plan actions, the env's step, scoring and the search itself, counted in
// physics substeps of the rollouts, and wall seconds per simulated second), and the snapshot
// restore alone; with --proposal, the same episode planned on top of a policy too, interleaved.
// Prints ratios; the key=value line: rollout_over_mjstep=, threads2_over_threads1=,
// restore_share=, ... and with a proposal proposal_substeps_over_plain_t2= (the forward pass's
// price per rollout step) and proposal_wall_s_per_sim_s_t2=.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "bench/bench_clock.h"
#include "bench/benchmarks.h"
#include "bench/physics_reference.h"
#include "common/eigen_policy.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "planner/planner_config.h"
#include "planner/planner_set.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using Clock = std::chrono::steady_clock;

struct SearchRate {
  double substeps_per_s = 0;      // physics substeps of the rollouts per wall second
  double seconds_per_replan = 0;
  double wall_s_per_sim_s = 0;    // what `juggle eval` reports for the planner
  // The planner's budget, independent of the machine, in executed-model control steps (a
  // planning model's steps count by their physics).
  double rollout_steps_per_sim_s = 0;
  int64_t rescues = 0;
  int64_t replans = 0;
};

// The planner driving its own episode (the start of stream (11, 0, 0); the next env of the
// stream if it ends) for `replans` × replan_every control steps on `threads` threads, through
// the evaluation's PlannerSet (a proposal, its trust search, the twin pools): what an
// evaluation spends, warm starts and rescues included. The planner's results do not depend on
// its threads, so every call with the same `proposal` visits the same states. `snapshots` (may
// be null) receives the state every 4th control step.
absl::StatusOr<SearchRate> PlannerEpisodeRate(std::shared_ptr<const JuggleSpec> spec,
                                              LoadedConfig config, int replans, int threads,
                                              std::shared_ptr<const EigenPolicy> proposal,
                                              std::vector<std::unique_ptr<EnvSnapshot>>* snapshots) {
  config::PlannerConfig& planner_config = *config.run.mutable_planner();
  planner_config.set_threads(threads);
  // The plain planner has no prior at all; the proposal's keeps the config's trust setting.
  planner_config.set_policy_prior(proposal != nullptr);
  if (proposal == nullptr) planner_config.set_search_prior_trust(false);
  absl::StatusOr<std::unique_ptr<planner::PlannerSet>> set =
      planner::PlannerSet::Create(spec, config, /*stream_base=*/0);
  if (!set.ok()) return set.status();
  if (proposal != nullptr) {
    if (absl::Status s = (*set)->SetProposal(proposal); !s.ok()) return s;
  }
  // Every env of the episode stays alive: the set knows its planners by the env's address.
  std::vector<std::unique_ptr<JuggleEnv>> envs;
  AdaptiveWalk walk(&spec->graph());
  auto next_env = [&] {
    envs.push_back(std::make_unique<JuggleEnv>(spec, Rng::ForStream(11, 0, envs.size())));
    envs.back()->Reset(walk);
    return envs.back().get();
  };
  JuggleEnv* env = next_env();
  int64_t control_steps = 0;
  float action[kNumActions];
  const auto start = Clock::now();
  const int64_t steps_to_run = int64_t(replans) * planner_config.replan_every();
  while (control_steps < steps_to_run) {
    if (snapshots != nullptr && control_steps % 4 == 0) snapshots->push_back(env->Snapshot());
    if (absl::Status s = (*set)->For(*env).Act(*env, action); !s.ok()) return s;
    ++control_steps;
    if (env->Step(action, walk).outcome != Outcome::kRunning) env = next_env();
  }
  const double seconds = SecondsSince(start);
  const planner::PlannerTotals totals = (*set)->totals();
  const double sim_s = control_steps * spec->control_dt();
  // Physics substeps the rollouts made: a planning model (planner.planning_model) takes
  // timestep_factor times fewer per control step; its exact_within_m steps take the executed
  // model's.
  const int substeps = spec->env().substeps();
  const double physics = double(totals.rollout_steps) *
                             (substeps / planner_config.planning_model().timestep_factor()) +
                         double(totals.exact_rollout_steps) * substeps;
  return SearchRate{physics / seconds,
                    seconds / std::max<int64_t>(totals.replans, 1), seconds / sim_s,
                    physics / substeps / sim_s, totals.rescues, totals.replans};
}

// One planner setting measured on 1 and 2 threads, the best of the repeats.
struct SettingRates {
  SearchRate one, two;
  void Keep(const SearchRate& a, const SearchRate& b) {
    if (a.substeps_per_s > one.substeps_per_s) one = a;
    if (b.substeps_per_s > two.substeps_per_s) two = b;
  }
};

void PrintSetting(const char* name, const SettingRates& r, double mj) {
  std::printf("%s, 1 thread: %.0f substeps/s (%.3f of bare mj_step), %.3f s per re-plan\n", name,
              r.one.substeps_per_s, r.one.substeps_per_s / mj, r.one.seconds_per_replan);
  std::printf("%s, 2 threads: %.0f substeps/s, %.3f s per re-plan = %.1f wall s per simulated s "
              "(%.0f rollout steps per simulated s; %ld rescues in %ld re-plans)\n",
              name, r.two.substeps_per_s, r.two.seconds_per_replan, r.two.wall_s_per_sim_s,
              r.two.rollout_steps_per_sim_s, static_cast<long>(r.two.rescues),
              static_cast<long>(r.two.replans));
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
  if (o.proposal != nullptr) {
    std::printf("and the same with the proposal %s as every plan's prior\n",
                o.proposal_path.c_str());
  }
  double mj = 0, restore_s = 1e9;
  SettingRates plain, proposed;
  std::vector<std::unique_ptr<EnvSnapshot>> visited;
  JuggleEnv env(*spec, Rng(0));
  auto measure = [&](std::shared_ptr<const EigenPolicy> policy, SettingRates* rates,
                     std::vector<std::unique_ptr<EnvSnapshot>>* snapshots) -> absl::Status {
    absl::StatusOr<SearchRate> a =
        PlannerEpisodeRate(*spec, *config, o.replans, 1, policy, snapshots);
    if (!a.ok()) return a.status();
    absl::StatusOr<SearchRate> b = PlannerEpisodeRate(*spec, *config, o.replans, 2, policy, nullptr);
    if (!b.ok()) return b.status();
    rates->Keep(*a, *b);
    return absl::OkStatus();
  };
  for (int r = 0; r < o.repeats; ++r) {  // interleaved, best of each
    mj = std::max(mj, BareMjStepRate(**spec, states));
    if (absl::Status s = measure(nullptr, &plain, visited.empty() ? &visited : nullptr); !s.ok()) {
      return s;
    }
    if (o.proposal != nullptr) {
      if (absl::Status s = measure(o.proposal, &proposed, nullptr); !s.ok()) return s;
    }
    const auto start = Clock::now();
    constexpr int kRestores = 2000;
    for (int i = 0; i < kRestores; ++i) (void)env.Restore(*visited[i % visited.size()]);
    restore_s = std::min(restore_s, SecondsSince(start) / kRestores);
    std::printf("repeat %d: mj_step/s %.0f  rollout substeps/s 1 thread %.0f  2 threads %.0f  "
                "restore %.1f us",
                r + 1, mj, plain.one.substeps_per_s, plain.two.substeps_per_s, restore_s * 1e6);
    if (o.proposal != nullptr) {
      std::printf("  with the proposal: 1 thread %.0f  2 threads %.0f",
                  proposed.one.substeps_per_s, proposed.two.substeps_per_s);
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  const SearchRate& one = plain.one;
  const SearchRate& two = plain.two;
  // A rollout restores once per candidate: its share of a rollout's time.
  const double steps_per_rollout = planner.horizon_steps();
  const double rollout_s = steps_per_rollout * (*spec)->env().substeps() / one.substeps_per_s;
  std::printf("bare mj_step: %.0f substeps/s per core\n", mj);
  PrintSetting("planner rollouts", plain, mj);
  if (o.proposal != nullptr) PrintSetting("with the proposal", proposed, mj);
  std::printf("mjstep_per_s=%.0f rollout_substeps_per_s_t1=%.0f rollout_substeps_per_s_t2=%.0f "
              "rollout_over_mjstep=%.3f threads2_over_threads1=%.3f restore_us=%.1f "
              "restore_share=%.4f replan_s_t2=%.3f wall_s_per_sim_s_t1=%.2f "
              "wall_s_per_sim_s_t2=%.2f rollout_steps_per_sim_s=%.0f rescues=%ld",
              mj, one.substeps_per_s, two.substeps_per_s, one.substeps_per_s / mj,
              two.substeps_per_s / one.substeps_per_s, restore_s * 1e6,
              restore_s / (rollout_s + restore_s), two.seconds_per_replan, one.wall_s_per_sim_s,
              two.wall_s_per_sim_s, two.rollout_steps_per_sim_s, static_cast<long>(two.rescues));
  if (o.proposal != nullptr) {
    // The proposal's own price is each rollout step's forward pass (substeps/s); its gain is
    // the search it saves (rollout steps per simulated s); wall time per simulated s is both.
    std::printf(" proposal_substeps_over_plain_t2=%.3f proposal_rollout_steps_per_sim_s=%.0f "
                "proposal_wall_s_per_sim_s_t2=%.2f proposal_rescues=%ld",
                proposed.two.substeps_per_s / two.substeps_per_s,
                proposed.two.rollout_steps_per_sim_s, proposed.two.wall_s_per_sim_s,
                static_cast<long>(proposed.two.rescues));
  }
  std::printf("\n");
  return absl::OkStatus();
}

}  // namespace juggle
