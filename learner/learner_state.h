// What a checkpoint holds besides the trainer's own state: the RunConfig it was trained with
// (stored: text with every file inlined and the compiled model, envs/stored_config.h, so that
// editing or deleting the config files never changes what a checkpoint loads) and the
// adaptive-walk edge counts. Shared by the learner, `eval`, `render`, `toss` and `export-policy`.
//
// Sections besides the trainer's: run_config (text), config_path (the file it was read from,
// for reports), model_mjb (since policy files of format 2; older checkpoints lack it and name
// their model through config_path), edge_counts, run_progress.
#ifndef JUGGLE_LEARNER_LEARNER_STATE_H_
#define JUGGLE_LEARNER_LEARNER_STATE_H_

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/adaptive_walk.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "envs/stored_config.h"
#include "learner/checkpoint.h"
#include "learner/ppo_trainer.h"

namespace juggle {

// How far a run has come, across --resume and --init_from: what `juggle train` reports as
// cumulative samples and training time.
struct RunProgress {
  int64_t samples = 0;        // env steps trained on
  double train_seconds = 0;   // wall time spent in training loops
};

// `config` is the run's stored config (the one its workers receive); `config_path` the file it
// was read from.
Sections SaveLearnerState(const StoredConfig& config, const std::string& config_path,
                          const PpoTrainer& trainer, const AdaptiveWalk& walk,
                          const RunProgress& progress);
// Restores trainer, walk and progress (zero for checkpoints written before progress was kept);
// on error none changes.
absl::Status RestoreLearnerState(const Sections& sections, PpoTrainer* trainer,
                                 AdaptiveWalk* walk, RunProgress* progress);

// A checkpoint file, or the newest readable checkpoint of a run directory
// (<dir>/checkpoints). NOT_FOUND / DATA_LOSS with the path in the message.
struct LoadedCheckpoint {
  std::string path;
  Sections sections;
  std::string config_path;  // the run config it was trained with (may be empty: old files)
  // Its stored config; none in checkpoints written before models were stored.
  std::optional<StoredConfig> stored;
};
absl::StatusOr<LoadedCheckpoint> LoadCheckpoint(const std::string& file_or_run_dir);

// The run config `checkpoint` was trained with. With a stored config: that copy (reads no file;
// its config_path is the recorded one) and no note. Older checkpoints: LoadRunConfig of the
// recorded config_path, as before stored models, and in `*note` one line for stderr saying that
// it is read from disk. Errors name the checkpoint: LoadStoredConfig's (with the hint to pass
// --config), FAILED_PRECONDITION for an old checkpoint that names no config, LoadRunConfig's.
absl::StatusOr<LoadedConfig> CheckpointConfig(const LoadedCheckpoint& checkpoint,
                                              std::string* note);

// The checkpoint's policy as a torch-free ExportedPolicy (`juggle export-policy`); `source` is
// left for the caller.
// `obs_dim`/`act_dim` are the config's env spec's.
absl::StatusOr<config::ExportedPolicy> ExportPolicyFromCheckpoint(const Sections& sections,
                                                                  const LoadedConfig& config,
                                                                  int obs_dim, int act_dim);

// The checkpoint's policy for `config` (which must describe the same graph and model).
absl::StatusOr<EigenPolicy> PolicyFromCheckpoint(const Sections& sections,
                                                 const LoadedConfig& config, int obs_dim,
                                                 int act_dim);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_STATE_H_
