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

Sections SaveLearnerState(const LoadedConfig& config, const PpoTrainer& trainer,
                          const AdaptiveWalk& walk);
// Restores trainer and walk; on error neither changes.
absl::Status RestoreLearnerState(const Sections& sections, PpoTrainer* trainer,
                                 AdaptiveWalk* walk);

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
absl::StatusOr<config::ExportedPolicy> ExportPolicyFromCheckpoint(const Sections& sections,
                                                                  const LoadedConfig& config);

// The checkpoint's policy for `config` (which must describe the same graph and model).
absl::StatusOr<EigenPolicy> PolicyFromCheckpoint(const Sections& sections,
                                                 const LoadedConfig& config);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_STATE_H_
