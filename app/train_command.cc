// `juggle train`: trains a policy on this machine — an env pool with Eigen inference collects
// unrolls, the PPO trainer updates, the new policy goes back to the pool. One progress line
// and one metrics.jsonl record per iteration; checkpoints in <run_dir>/checkpoints.
// (The gRPC service will run the same loop across processes.)
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sys/stat.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/flags.h"
#include "app/learner_state.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "google/protobuf/text_format.h"
#include "learner/checkpoint.h"
#include "learner/ppo_trainer.h"
#include "worker/env_pool.h"
#include "worker/rollout_collector.h"

namespace juggle {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

const std::vector<FlagSpec>& TrainFlags() {
  static const auto* specs = new std::vector<FlagSpec>{
      {"config", "configs/right_foot.textproto", "run config (protobuf text format)"},
      {"run_dir", "", "run directory (default runs/<config name>)"},
      {"iterations", "0", "stop after this many iterations (0: the config's ppo.iterations)"},
      {"minutes", "0", "stop after this many minutes of wall time (0: no limit)"},
      {"checkpoint_every", "10", "iterations between checkpoints"},
      {"resume", "false", "continue from the newest readable checkpoint in the run directory"},
      {"envs", "0", "number of envs (0: the config's)"},
      {"threads", "0", "env threads (0: the config's)"},
  };
  return *specs;
}

int Fail(const absl::Status& s) {
  std::fprintf(stderr, "error: %s\n", std::string(s.message()).c_str());
  return 1;
}

}  // namespace

int RunTrain(int argc, char** argv, int first) {
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, TrainFlags());
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle train [flags]\n%s", Flags::Usage(TrainFlags()).c_str());
    return 0;
  }
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(flags->Get("config"));
  if (!config.ok()) return Fail(config.status());
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = JuggleSpec::Create(*config);
  if (!spec.ok()) return Fail(spec.status());
  const config::RunConfig& run = config->run;
  const int envs = *flags->GetInt("envs") > 0 ? *flags->GetInt("envs") : run.sampling().num_envs();
  const int threads =
      *flags->GetInt("threads") > 0 ? *flags->GetInt("threads") : run.sampling().num_threads();
  const int64_t iterations =
      *flags->GetInt("iterations") > 0 ? *flags->GetInt("iterations") : run.ppo().iterations();
  const double minutes = *flags->GetDouble("minutes");
  const int64_t checkpoint_every = std::max<int64_t>(1, *flags->GetInt("checkpoint_every"));
  const std::string run_dir = flags->Get("run_dir").empty()
                                  ? absl::StrCat("runs/", run.name().empty() ? "run" : run.name())
                                  : flags->Get("run_dir");
  ::mkdir("runs", 0755);
  ::mkdir(run_dir.c_str(), 0755);

  auto pool = EnvPool::Create(*spec, envs, threads, run.seed());
  if (!pool.ok()) return Fail(pool.status());
  const int obs_dim = (*spec)->obs_dim();
  PpoTrainer trainer(run.model(), run.ppo(), obs_dim, kNumActions, run.seed());
  CheckpointDir checkpoints(run_dir + "/checkpoints");
  if (flags->GetBool("resume")) {
    absl::StatusOr<CheckpointDir::Loaded> loaded = checkpoints.LoadLatest();
    if (!loaded.ok()) return Fail(loaded.status());
    for (const std::string& skipped : loaded->skipped) {
      std::fprintf(stderr, "warning: skipped unreadable checkpoint: %s\n", skipped.c_str());
    }
    if (absl::Status s = RestoreLearnerState(loaded->sections, &trainer, (*pool)->walk()); !s.ok()) {
      return Fail(s);
    }
    std::printf("resumed from %s at iteration %ld\n", loaded->path.c_str(),
                static_cast<long>(trainer.iteration()));
  }
  RolloutCollector collector(pool->get(), run.ppo().unroll_length(), run.seed());

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  std::ofstream metrics(run_dir + "/metrics.jsonl", std::ios::app);
  const double control_dt = (*spec)->control_dt();
  std::printf("training %s: %d nodes, obs %d, %d envs x %d steps = %d samples/iteration, "
              "%d threads; run dir %s\n",
              run.name().c_str(), (*spec)->graph().num_nodes(), obs_dim, envs,
              run.ppo().unroll_length(), envs * run.ppo().unroll_length(), threads,
              run_dir.c_str());
  const auto start = std::chrono::steady_clock::now();
  int64_t total_samples = 0;
  UnrollBatch batch;
  while (!g_stop) {
    if (iterations > 0 && trainer.iteration() >= iterations) break;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (minutes > 0 && elapsed >= minutes * 60) break;
    const auto t0 = std::chrono::steady_clock::now();
    absl::StatusOr<EigenPolicy> policy =
        EigenPolicy::Create(run.model(), trainer.ExportPolicy(), obs_dim, kNumActions);
    if (!policy.ok()) return Fail(policy.status());
    collector.Collect(*policy, &batch);
    const auto t1 = std::chrono::steady_clock::now();
    absl::StatusOr<UpdateStats> update = trainer.Update(batch);
    if (!update.ok()) return Fail(update.status());
    const auto t2 = std::chrono::steady_clock::now();
    const EpisodeStats episodes = (*pool)->TakeStats();
    const double sample_s = std::chrono::duration<double>(t1 - t0).count();
    const double update_s = std::chrono::duration<double>(t2 - t1).count();
    const double iter_s = sample_s + update_s;
    total_samples += batch.num_samples();
    const double samples_per_s = batch.num_samples() / iter_s;
    const std::string line = absl::StrFormat(
        "{\"iteration\": %d, \"samples\": %d, \"samples_per_s\": %.1f, \"sim_s_per_s\": %.2f, "
        "\"mean_return\": %.4f, \"mean_episode_len\": %.2f, \"completions_per_episode\": %.3f, "
        "\"episodes\": %d, \"policy_lag\": 0, \"iteration_s\": %.3f, \"sample_s\": %.3f, "
        "\"update_s\": %.3f, \"value_loss\": %.5f, \"approx_kl\": %.5f, \"clip_fraction\": %.4f, "
        "\"actor_lr\": %.6f, \"wall_s\": %.1f}",
        trainer.iteration(), total_samples, samples_per_s, samples_per_s * control_dt,
        episodes.mean_return(), episodes.mean_length(), episodes.mean_completions(),
        episodes.episodes, iter_s, sample_s, update_s, update->value_loss, update->approx_kl,
        update->clip_fraction, update->actor_lr,
        std::chrono::duration<double>(t2 - start).count());
    metrics << line << "\n";
    metrics.flush();
    std::printf("iter %5ld  samples %9ld  %7.0f samples/s  %5.1f sim-s/s  return %7.3f  "
                "ep_len %6.1f  completions/ep %5.2f  lag 0  %.2fs (sample %.2f, update %.2f)\n",
                static_cast<long>(trainer.iteration()), static_cast<long>(total_samples),
                samples_per_s, samples_per_s * control_dt, episodes.mean_return(),
                episodes.mean_length(), episodes.mean_completions(), iter_s, sample_s, update_s);
    std::fflush(stdout);
    if (trainer.iteration() % checkpoint_every == 0) {
      absl::StatusOr<std::string> path = checkpoints.Save(
          trainer.iteration(), SaveLearnerState(*config, trainer, *(*pool)->walk()));
      if (!path.ok()) return Fail(path.status());
    }
  }
  absl::StatusOr<std::string> path = checkpoints.Save(
      trainer.iteration(), SaveLearnerState(*config, trainer, *(*pool)->walk()));
  if (!path.ok()) return Fail(path.status());
  std::printf("stopped at iteration %ld; checkpoint %s\n", static_cast<long>(trainer.iteration()),
              path->c_str());
  return 0;
}

}  // namespace juggle
