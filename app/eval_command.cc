// `juggle eval`: runs a trained policy without exploration noise (the mean action), or the
// zero-action baseline, for a set of seeded episodes side by side, and reports the juggles
// distribution and how episodes ended, the per-node table, optionally the force sweep
// (eval/tables.h) and JSON lines. The last line is key=value pairs (eval/summary.h).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/policy_source.h"
#include "common/file_io.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "eval/summary.h"
#include "eval/tables.h"

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
  std::string json;
  bool force_sweep = false;
  double force_step = 1.0;
  double force_max = 5.0;
  double min_median_juggles = 10;
};

// Writes `lines` (JSON objects) to `path`, one per line.
absl::Status WriteJsonLines(const std::string& path, const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) absl::StrAppend(&text, line, "\n");
  return WriteFile(path, text);
}

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

  if (!f.json.empty()) {
    // Fail before evaluating, not after.
    if (absl::Status s = WriteJsonLines(f.json, {}); !s.ok()) return Fail(s);
  }
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
  const std::vector<NodeRow> nodes =
      NodeTable(report->episodes, (*spec)->graph(), (*spec)->outcome_names());
  std::printf("%s", FormatNodeTable(nodes).c_str());
  std::vector<std::string> json = {SummaryJson(summary)};
  for (const NodeRow& row : nodes) json.push_back(NodeRowJson(row));

  if (f.force_sweep) {
    ForceSweepOptions sweep;
    sweep.magnitudes.clear();
    for (int k = 0; k * f.force_step <= f.force_max + 1e-9; ++k) {
      sweep.magnitudes.push_back(k * f.force_step);
    }
    sweep.min_median_juggles = f.min_median_juggles;
    sweep.episodes = options;
    sweep.episodes.record = false;
    // A controller of its own: the gate statistics above stay those of the plain evaluation.
    std::unique_ptr<Controller> sweep_controller;
    if (source) {
      sweep_controller = std::make_unique<PolicyController>(source->policy);
    } else {
      sweep_controller = std::make_unique<ZeroController>((*spec)->act_dim());
    }
    std::printf("force sweep: constant force on the ball, %zu magnitudes per direction, "
                "%d episodes each, pass: median juggles >= %g\n",
                sweep.magnitudes.size(), f.episodes, f.min_median_juggles);
    absl::StatusOr<ForceSweepReport> swept =
        RunForceSweep(config, sweep_controller.get(), sweep, [](const std::string& l) {
          std::printf("  %s\n", l.c_str());
          std::fflush(stdout);
        });
    if (!swept.ok()) return Fail(swept.status());
    std::printf("%-9s %12s\n", "direction", "max_force_n");
    for (const std::string& direction : swept->directions) {
      // "none": even the smallest force fails.
      const double force = swept->max_force_n.at(direction);
      std::printf("%-9s %12s\n", direction.c_str(),
                  force < 0 ? "none" : absl::StrFormat("%.3f", force).c_str());
      absl::StrAppend(&line, absl::StrFormat(" max_force_%s=%g", direction, force));
      json.push_back(ForceLimitJson(direction, force, f.min_median_juggles));
    }
    for (const auto& [direction, why] : swept->unsupported) {
      std::printf("%-9s %12s  (%s)\n", direction.c_str(), "-", why.c_str());
    }
    for (const ForceSweepRow& row : swept->rows) json.push_back(ForceRowJson(row));
  }
  if (!f.json.empty()) {
    if (absl::Status s = WriteJsonLines(f.json, json); !s.ok()) return Fail(s);
    std::printf("wrote %zu JSON lines to %s\n", json.size(), f.json.c_str());
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
  cmd->add_option("--json", f->json,
                  "also write the tables as JSON lines: summary, one per node, and with "
                  "--force-sweep one per direction and force (docs/results.md)");
  cmd->add_flag("--force-sweep", f->force_sweep,
                "robustness sweep (paper Table 1): a constant force on the ball along +-x, +-y, "
                "+-z at 0, step, 2*step, ... up to --force-max, each with the same episodes");
  cmd->add_option("--force-step", f->force_step, "force sweep step, N")
      ->check(Between(1e-6, 1000))
      ->capture_default_str();
  cmd->add_option("--force-max", f->force_max, "largest force of the sweep, N")
      ->check(Between(0, 1000))
      ->capture_default_str();
  cmd->add_option("--min-median-juggles", f->min_median_juggles,
                  "a force passes when the median juggles stay at or above this")
      ->check(AtLeast(0))
      ->capture_default_str();
  return [f] { return Evaluate(*f); };
}

}  // namespace juggle
