// `juggle simulate`: steps an env pool with a fixed action policy (zero or uniform random) or
// the planner, and prints progress and episode statistics.
#include <chrono>
#include <cstdio>
#include <vector>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/controller_factory.h"
#include "app/planner_flags.h"
#include "common/rng.h"
#include "envs/registry.h"
#include "worker/env_pool.h"

namespace juggle {
namespace {

struct SimulateFlags {
  std::string config = "configs/right_foot.textproto";
  double seconds = 20;
  int envs = 0, threads = 0;
  int64_t seed = -1;
  std::string policy = "zero";
  PlannerFlags planner;
};

int Simulate(const SimulateFlags& f) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(f.config);
  if (!config.ok()) return Fail(config.status());
  if (absl::Status s = ApplyPlannerFlags(f.planner, &*config); !s.ok()) return Fail(s);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return Fail(spec.status());
  const config::RunConfig& run = config->run;
  const int num_envs = f.envs > 0 ? f.envs : run.sampling().num_envs();
  const int num_threads = f.threads > 0 ? f.threads : run.sampling().num_threads();
  const uint64_t run_seed = f.seed >= 0 ? f.seed : run.seed();
  auto pool = EnvPool::Create(*spec, num_envs, num_threads, run_seed);
  if (!pool.ok()) return Fail(pool.status());
  const double control_dt = (*spec)->control_dt();
  const int total_steps = static_cast<int>(f.seconds / control_dt + 0.5);
  const int report_every = std::max(1, static_cast<int>(1.0 / control_dt));  // 1 sim second
  std::printf("simulating %d envs on %d threads for %.1f s each (%d control steps), seed %lu\n",
              num_envs, num_threads, f.seconds, total_steps, static_cast<unsigned long>(run_seed));
  std::vector<float> actions(size_t(num_envs) * (*spec)->act_dim(), 0.0f);
  Rng action_rng(run_seed ^ 0xA5A5A5A5ULL);
  std::unique_ptr<Controller> planner;
  std::vector<const Env*> envs;
  if (f.policy == "planner") {
    ControllerChoice choice;
    choice.kind = "planner";
    absl::StatusOr<std::unique_ptr<Controller>> p = MakeController(choice, *spec, *config);
    if (!p.ok()) return Fail(p.status());
    planner = std::move(*p);
    for (int i = 0; i < num_envs; ++i) envs.push_back(&(*pool)->env(i));
  }
  (*pool)->Reset();
  EpisodeCounters total;
  const auto start = std::chrono::steady_clock::now();
  for (int step = 1; step <= total_steps; ++step) {
    if (f.policy == "random") {
      for (float& a : actions) a = static_cast<float>(action_rng.Uniform(-1, 1));
    } else if (planner) {
      planner->Act(envs.data(), nullptr, num_envs, actions.data());
    }
    (*pool)->Step(actions.data());
    if (step % report_every == 0 || step == total_steps) {
      total.Add((*pool)->TakeStats());
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("t=%6.1fs  steps/s %8.0f  sim s/s %6.1f  episodes %5ld  mean_return %.3f  "
                  "mean_len %.1f  juggles/ep %.2f\n",
                  step * control_dt, total.steps / wall, total.steps * control_dt / wall,
                  static_cast<long>(total.episodes), total.mean_return(), total.mean_length(),
                  total.mean_juggles());
      std::fflush(stdout);
    }
  }
  const std::vector<std::string> names = (*spec)->outcome_names();
  std::string outcomes;
  for (int o = 1; o < static_cast<int>(names.size()); ++o) {
    absl::StrAppend(&outcomes, " ", names[o], "=", total.outcome(o));
  }
  std::printf("episodes=%ld mean_return=%.4f mean_length=%.2f mean_completions=%.3f "
              "mean_juggles=%.3f%s\n",
              static_cast<long>(total.episodes), total.mean_return(), total.mean_length(),
              total.mean_completions(), total.mean_juggles(), outcomes.c_str());
  return 0;
}

}  // namespace

CommandBody AddSimulateCommand(CLI::App* cmd) {
  auto f = std::make_shared<SimulateFlags>();
  cmd->add_option("--config", f->config, "run config (protobuf text format)")->capture_default_str();
  cmd->add_option("--seconds", f->seconds, "simulated seconds per env")
      ->check(Between(0, 1e6))
      ->capture_default_str();
  cmd->add_option("--envs", f->envs, "number of envs (0: the config's sampling.num_envs)")
      ->check(Between(0, 100000))
      ->capture_default_str();
  cmd->add_option("--threads", f->threads, "threads (0: the config's sampling.num_threads)")
      ->check(Between(0, 1024))
      ->capture_default_str();
  cmd->add_option("--seed", f->seed, "run seed (-1: the config's seed)")
      ->check(AtLeast(-1))
      ->capture_default_str();
  cmd->add_option("--policy,--controller", f->policy,
                  "what acts: zero | random (uniform in [-1, 1]) | planner (the config's "
                  "planner settings, docs/planner.md)")
      ->check(CLI::IsMember({"zero", "random", "planner"}))
      ->capture_default_str();
  AddPlannerFlags(cmd, &f->planner);
  return [f] { return Simulate(*f); };
}

}  // namespace juggle
