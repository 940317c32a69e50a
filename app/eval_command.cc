// `juggle eval`: runs a trained policy without exploration noise (the mean action), or the
// zero-action baseline, for a set of seeded episodes side by side, and reports the juggles
// distribution and how episodes ended. The last line is key=value pairs (eval/summary.h).
#include <cstdio>
#include <memory>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/policy_source.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "eval/summary.h"

namespace juggle {
namespace {

// Episode seeds no training run uses: training streams are (run seed, worker slot, env), with
// run seeds and slots far below this.
constexpr int64_t kHeldOutSeed = 1000000;

struct EvalFlags {
  std::string policy;
  std::string config;
  bool zero_action = false;
  int episodes = 50;
  int64_t seed = kHeldOutSeed;
  double max_seconds = 60;
  std::string record;
};

int Evaluate(const EvalFlags& f) {
  if (f.policy.empty() == !f.zero_action) {
    return UsageError("give exactly one of --policy=PATH and --zero-action");
  }
  std::optional<PolicySource> source;
  LoadedConfig config;
  if (!f.zero_action) {
    absl::StatusOr<PolicySource> loaded = LoadPolicySource(f.policy, f.config);
    if (!loaded.ok()) return Fail(loaded.status());
    source = std::move(*loaded);
    config = source->config;
    std::printf("policy %s\n", source->path.c_str());
  } else {
    if (f.config.empty()) return UsageError("--zero-action needs --config");
    absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(f.config);
    if (!loaded.ok()) return Fail(loaded.status());
    config = std::move(*loaded);
  }
  absl::StatusOr<const EnvFamily*> family = FamilyOf(config.run);
  if (!family.ok()) return Fail(family.status());
  (*family)->ConfigureForEvaluation(f.max_seconds, &config.run);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config);
  if (!spec.ok()) return Fail(spec.status());

  std::unique_ptr<Controller> controller;
  PolicyController* policy_controller = nullptr;
  if (source) {
    auto p = std::make_unique<PolicyController>(source->policy, /*keep_gates=*/true);
    policy_controller = p.get();
    controller = std::move(p);
  } else {
    controller = std::make_unique<ZeroController>((*spec)->act_dim());
  }
  EpisodeOptions options;
  options.episodes = f.episodes;
  options.seed = static_cast<uint64_t>(f.seed);
  options.record = !f.record.empty();
  options.config_path = config.config_path;
  absl::StatusOr<EpisodeReport> report = RunEpisodes(*spec, controller.get(), options);
  if (!report.ok()) return Fail(report.status());
  if (report->trajectory) {
    if (absl::Status s = WriteTrajectory(*report->trajectory, f.record); !s.ok()) return Fail(s);
    std::printf("recorded %d episodes (%.2f s) to %s\n", f.episodes,
                report->trajectory->duration(), f.record.c_str());
  }
  const EvalSummary summary =
      Summarize(report->episodes, (*spec)->control_dt(), (*spec)->outcome_names());
  std::string line = absl::StrCat("policy=", controller->name(), " seed=", f.seed,
                                  " max_seconds=", f.max_seconds, " ", SummaryLine(summary));
  if (policy_controller != nullptr && policy_controller->gates().rows() > 0) {
    const GateStatistics g = ComputeGateStatistics(policy_controller->gates());
    absl::StrAppend(&line, absl::StrFormat(" gate_specialization=%.3f gate_utilization=%.3f",
                                           g.specialization, g.utilization));
  }
  std::printf("%s\n", line.c_str());
  return 0;
}

}  // namespace

CommandBody AddEvalCommand(CLI::App* cmd) {
  auto f = std::make_shared<EvalFlags>();
  cmd->add_option("--policy,--checkpoint", f->policy,
                  "checkpoint file (.jglc), run directory (its newest checkpoint) or exported "
                  "policy (.jglpolicy)");
  cmd->add_option("--config", f->config,
                  "run config (default: the one recorded with the policy; required with "
                  "--zero-action)");
  cmd->add_flag("--zero-action", f->zero_action, "evaluate the zero-action baseline instead");
  cmd->add_option("--episodes", f->episodes, "episodes, one per env seed")
      ->check(Between(1, 100000))
      ->capture_default_str();
  cmd->add_option("--seed", f->seed,
                  "episode i starts from stream (seed, 0, i); the default is held out from "
                  "training")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--max_seconds", f->max_seconds,
                  "episode length limit in simulated seconds (0: the config's)")
      ->check(Between(0, 86400))
      ->capture_default_str();
  cmd->add_option("--record", f->record,
                  "write every episode, one after another, as a trajectory (docs/recording.md)");
  return [f] { return Evaluate(*f); };
}

}  // namespace juggle
