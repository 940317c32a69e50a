// When and how strongly the policy imitates its teacher (proto/imitation.proto): pretraining
// (cloning only) for the first pretrain_iterations learner iterations, then PPO with the
// imitation weight × decay^k (k: iterations since pretraining) above its floor. Cloning needs
// min_buffer demonstrations; until then a pretraining iteration trains only the critic. The
// label error of each action is weighted by 1 / max(its label variance, min_label_std²).
#ifndef JUGGLE_LEARNER_IMITATION_SCHEDULE_H_
#define JUGGLE_LEARNER_IMITATION_SCHEDULE_H_

#include <cstdint>

#include "learner/demo_buffer.h"
#include "learner/ppo_trainer.h"
#include "proto/imitation.pb.h"

namespace juggle {

// The imitation term of the update that makes learner iteration `iteration` + 1 (the trainer's
// iteration() before it). `demos` may be null (no demonstrations: a plain PPO term).
ImitationTerm ImitationFor(const config::ImitationConfig& config, int64_t iteration,
                           const DemoBuffer* demos);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_IMITATION_SCHEDULE_H_
