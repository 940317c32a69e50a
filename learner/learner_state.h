// What a checkpoint holds besides the trainer's own state: the RunConfig it was trained with
// and the adaptive-walk edge counts. Shared by `train`, `eval` and (later) the learner service.
#ifndef JUGGLE_LEARNER_LEARNER_STATE_H_
#define JUGGLE_LEARNER_LEARNER_STATE_H_

#include "absl/status/status.h"
#include "common/adaptive_walk.h"
#include "common/config_loader.h"
#include "learner/checkpoint.h"
#include "learner/ppo_trainer.h"

namespace juggle {

Sections SaveLearnerState(const LoadedConfig& config, const PpoTrainer& trainer,
                          const AdaptiveWalk& walk);
// Restores trainer and walk; on error neither changes.
absl::Status RestoreLearnerState(const Sections& sections, PpoTrainer* trainer,
                                 AdaptiveWalk* walk);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_STATE_H_
