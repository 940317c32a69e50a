// What a checkpoint holds besides the trainer's own state: the RunConfig it was trained with
// and the adaptive-walk edge counts. Shared by `train`, `eval` and (later) the learner service.
#ifndef JUGGLE_LEARNER_LEARNER_STATE_H_
#define JUGGLE_LEARNER_LEARNER_STATE_H_

#include "absl/status/status.h"
#include "common/adaptive_walk.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "learner/checkpoint.h"
#include "learner/ppo_trainer.h"

namespace juggle {

// How far a run has come, across --resume and --init_from: what `juggle train` reports as
// cumulative samples and training time.
struct RunProgress {
  int64_t samples = 0;        // env steps trained on
  double train_seconds = 0;   // wall time spent in training loops
};

Sections SaveLearnerState(const LoadedConfig& config, const PpoTrainer& trainer,
                          const AdaptiveWalk& walk, const RunProgress& progress);
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
};
absl::StatusOr<LoadedCheckpoint> LoadCheckpoint(const std::string& file_or_run_dir);

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
