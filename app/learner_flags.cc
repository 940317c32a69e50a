#include "app/learner_flags.h"

#include <cstdio>
#include <filesystem>

#include "absl/strings/str_cat.h"
#include "envs/registry.h"
#include "envs/stored_config.h"
#include "learner/checkpoint.h"
#include "learner/learner_state.h"

namespace juggle {
namespace {

constexpr char kDefaultConfig[] = "configs/right_foot.textproto";

std::string DefaultRunDir(const config::RunConfig& run) {
  return absl::StrCat("runs/", run.name().empty() ? "run" : run.name());
}

// The config a resumed run continues under. Without --config: the copy stored in its newest
// checkpoint (`named` is not read), or, for a checkpoint written before configs were stored,
// the default config as before. With --config: that config, as before, and a note when it
// differs from the stored copy (its text or its compiled model). `seed` >= 0 overrides the
// seed of either.
absl::StatusOr<LoadedConfig> ResumedConfig(const std::string& run_dir, bool config_given,
                                           const std::string& named, int64_t seed) {
  absl::StatusOr<LoadedCheckpoint> parsed = LoadCheckpoint(run_dir);  // its newest readable one
  if (!parsed.ok()) return parsed.status();
  if (!parsed->stored.has_value()) {
    if (!config_given) {
      std::fprintf(stderr,
                   "note: %s is an old-format checkpoint without a stored config: resuming "
                   "under %s\n",
                   parsed->path.c_str(), named.c_str());
    }
    return LoadRunConfig(named);
  }
  if (!config_given) {
    absl::StatusOr<LoadedConfig> stored = CheckpointConfig(*parsed, nullptr);
    if (!stored.ok()) return stored.status();
    std::printf("resuming under the run config stored in %s (first read from %s)\n",
                parsed->path.c_str(), stored->config_path.c_str());
    return stored;
  }
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(named);
  if (!config.ok()) return config.status();
  if (seed >= 0) config->run.set_seed(static_cast<uint64_t>(seed));
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return spec.status();
  const StoredConfig now = StoreConfig(*config, **spec);
  if (now.text != parsed->stored->text || now.model_mjb != parsed->stored->model_mjb) {
    std::fprintf(stderr,
                 "note: --config=%s differs from the run config stored in %s (%s): training "
                 "continues under --config; omit --config to resume under the stored copy\n",
                 named.c_str(), parsed->path.c_str(),
                 now.text != parsed->stored->text ? "its settings" : "its compiled model");
  }
  return config;
}

// --init_from: a new run that starts from another run's checkpoint (fine-tuning under another
// config, e.g. toss in-loop training). The checkpoint is copied into <run_dir>/checkpoints,
// which must hold none yet; the run then resumes from it.
absl::Status SeedRunFromCheckpoint(const std::string& source, const std::string& run_dir) {
  CheckpointDir dir(run_dir + "/checkpoints");
  if (!dir.List().empty()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "--init_from: run directory ", run_dir, " already holds checkpoints (newest ",
        dir.List().front(), "); choose another --run_dir, or --resume without --init_from"));
  }
  absl::StatusOr<LoadedCheckpoint> checkpoint = LoadCheckpoint(source);
  if (!checkpoint.ok()) return checkpoint.status();
  const std::string name = std::filesystem::path(checkpoint->path).filename().string();
  std::error_code error;
  std::filesystem::create_directories(dir.dir(), error);
  if (error) {
    return absl::PermissionDeniedError(absl::StrCat("cannot create ", dir.dir(), ": ",
                                                    error.message()));
  }
  if (absl::Status s = WriteCheckpointFile(dir.dir() + "/" + name, checkpoint->sections); !s.ok()) {
    return s;
  }
  std::printf("starting from %s\n", checkpoint->path.c_str());
  return absl::OkStatus();
}

}  // namespace

void AddLearnerFlags(CLI::App* cmd, LearnerFlags* f) {
  cmd->add_option("--config", f->config,
                  "run config (protobuf text format; default: when resuming, the copy stored in "
                  "the newest checkpoint, else configs/right_foot.textproto)");
  cmd->add_option("--run_dir", f->run_dir,
                  "run directory: checkpoints/ and metrics.jsonl (default runs/<name>)");
  cmd->add_flag("--resume", f->resume,
                "continue from the newest readable checkpoint in the run directory");
  cmd->add_flag("--resume_if_any", f->resume_if_any,
                "--resume when the run directory holds a checkpoint, else start a new run (for "
                "schedulers that restart the learner: Kubernetes, Slurm requeue)");
  cmd->add_option("--init_from", f->init_from,
                  "start a new run from this checkpoint (file or run directory): fine-tuning "
                  "under this config");
  cmd->add_option("--iterations", f->iterations,
                  "stop after this many iterations (0: the config's ppo.iterations)")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--minutes", f->minutes, "stop after this many minutes of this process (a resumed run counts from its "
                  "restart; 0: no limit)")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--seed", f->seed, "run seed (-1: the config's seed)")
      ->check(AtLeast(-1))
      ->capture_default_str();
  cmd->add_option("--metrics_port", f->metrics_port,
                  "HTTP port of /metrics and the dashboard (-1: the config's "
                  "service.metrics_port; 0: off, as in the config; unset in both: off, "
                  "except `train`, which picks a free port)")
      ->check(Between(-1, 65535))
      ->capture_default_str();
}

absl::StatusOr<LearnerOptions> MakeLearnerOptions(const LearnerFlags& flags) {
  const bool config_given = !flags.config.empty();
  const std::string named = config_given ? flags.config : kDefaultConfig;
  LearnerOptions o;
  o.run_dir = flags.run_dir;
  if (o.run_dir.empty()) {
    // The default run directory is named after the config.
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(named);
    if (!config.ok()) return config.status();
    o.run_dir = DefaultRunDir(config->run);
  }
  o.resume = flags.resume;
  o.max_iterations = flags.iterations;
  o.max_minutes = flags.minutes;
  o.metrics_port = flags.metrics_port;
  std::error_code error;
  std::filesystem::create_directories(o.run_dir, error);
  if (error) {
    return absl::PermissionDeniedError(absl::StrCat("cannot create run directory ", o.run_dir,
                                                    ": ", error.message()));
  }
  if (flags.resume_if_any) {
    if (!flags.init_from.empty()) {
      return absl::InvalidArgumentError(
          "--init_from starts a new run; it cannot be combined with --resume_if_any");
    }
    // A folder of unreadable checkpoints still resumes, and so fails loudly: never start over
    // silently on top of a run.
    o.resume = o.resume || !CheckpointDir(o.run_dir + "/checkpoints").List().empty();
    std::printf("%s\n", o.resume ? "resuming from the run directory's newest checkpoint"
                                  : "no checkpoint in the run directory: starting a new run");
  }
  if (!flags.init_from.empty()) {
    if (o.resume) {
      return absl::InvalidArgumentError(
          "--init_from starts a new run; it cannot be combined with --resume");
    }
    if (absl::Status s = SeedRunFromCheckpoint(flags.init_from, o.run_dir); !s.ok()) return s;
  }
  // --init_from fine-tunes under the named config; a resumed run continues under its own.
  absl::StatusOr<LoadedConfig> config =
      o.resume ? ResumedConfig(o.run_dir, config_given, named, flags.seed) : LoadRunConfig(named);
  if (!config.ok()) return config.status();
  if (flags.seed >= 0) config->run.set_seed(static_cast<uint64_t>(flags.seed));
  o.config = std::move(*config);
  if (!flags.init_from.empty()) o.resume = true;  // from the copied checkpoint
  return o;
}

}  // namespace juggle
