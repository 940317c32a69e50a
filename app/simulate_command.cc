// `juggle simulate`: steps an env pool with a fixed action policy (zero or uniform random) and
// prints progress and episode statistics.
#include <chrono>
#include <cstdio>
#include <vector>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "common/rng.h"
#include "worker/env_pool.h"
#include "common/env_family.h"
#include "worker/env_registry.h"

namespace juggle {
namespace {

const std::vector<FlagSpec>& SimulateFlags() {
  static const auto* specs = new std::vector<FlagSpec>{
      {"config", "configs/right_foot.textproto", "run config (protobuf text format)"},
      {"seconds", "20", "simulated seconds per env"},
      {"envs", "0", "number of envs (0: the config's sampling.num_envs)"},
      {"threads", "0", "threads (0: the config's sampling.num_threads)"},
      {"seed", "-1", "run seed (-1: the config's seed)"},
      {"policy", "zero", "action policy: zero | random (uniform in [-1, 1])"},
  };
  return *specs;
}

int Fail(const absl::Status& status) {
  std::fprintf(stderr, "error: %s\n", std::string(status.message()).c_str());
  return 1;
}

}  // namespace

int RunSimulate(int argc, char** argv, int first) {
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, SimulateFlags());
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle simulate [flags]\n%s", Flags::Usage(SimulateFlags()).c_str());
    return 0;
  }
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(flags->Get("config"));
  if (!config.ok()) return Fail(config.status());
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return Fail(spec.status());

  auto envs = flags->GetInt("envs");
  auto threads = flags->GetInt("threads");
  auto seed = flags->GetInt("seed");
  auto seconds = flags->GetDouble("seconds");
  for (const absl::Status& s : {envs.status(), threads.status(), seed.status(), seconds.status()}) {
    if (!s.ok()) return Fail(s);
  }
  const std::string policy = flags->Get("policy");
  if (policy != "zero" && policy != "random") {
    return Fail(absl::InvalidArgumentError("--policy must be zero or random"));
  }
  const config::RunConfig& run = config->run;
  const int num_envs = *envs > 0 ? *envs : run.sampling().num_envs();
  const int num_threads = *threads > 0 ? *threads : run.sampling().num_threads();
  const uint64_t run_seed = *seed >= 0 ? *seed : run.seed();
  auto pool = EnvPool::Create(*spec, num_envs, num_threads, run_seed);
  if (!pool.ok()) return Fail(pool.status());

  const double control_dt = ControlDt(*config);
  const int total_steps = static_cast<int>(*seconds / control_dt + 0.5);
  const int report_every = std::max(1, static_cast<int>(1.0 / control_dt));  // 1 sim second
  std::printf("simulating %d envs on %d threads for %.1f s each (%d control steps), seed %lu\n",
              num_envs, num_threads, *seconds, total_steps,
              static_cast<unsigned long>(run_seed));

  std::vector<float> actions(size_t(num_envs) * (*spec)->act_dim(), 0.0f);
  Rng action_rng(run_seed ^ 0xA5A5A5A5ULL);
  (*pool)->Reset();
  EpisodeCounters total;
  const auto start = std::chrono::steady_clock::now();
  for (int step = 1; step <= total_steps; ++step) {
    if (policy == "random") {
      for (float& a : actions) a = static_cast<float>(action_rng.Uniform(-1, 1));
    }
    (*pool)->Step(actions.data());
    if (step % report_every == 0 || step == total_steps) {
      total.Add((*pool)->TakeStats());
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("t=%6.1fs  steps/s %8.0f  sim s/s %6.1f  episodes %5ld  mean_return %.3f  "
                  "mean_len %.1f  completions/ep %.2f\n",
                  step * control_dt, total.steps / wall, total.steps * control_dt / wall,
                  static_cast<long>(total.episodes), total.mean_return(), total.mean_length(),
                  total.mean_completions());
      std::fflush(stdout);
    }
  }
  std::string outcomes;
  for (int o = 1; o < static_cast<int>(Outcome::kNumOutcomes); ++o) {
    absl::StrAppend(&outcomes, " ", OutcomeName(static_cast<Outcome>(o)), "=", total.outcome(o));
  }
  std::printf("episodes=%ld mean_return=%.4f mean_length=%.2f mean_completions=%.3f%s\n",
              static_cast<long>(total.episodes), total.mean_return(), total.mean_length(),
              total.mean_completions(), outcomes.c_str());
  return 0;
}

}  // namespace juggle
