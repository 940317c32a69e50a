// Loading MuJoCo models for every env family: from MJCF (the learner, tools) or from the
// compiled bytes the learner ships to workers. Also silences MuJoCo's process-global warning
// handler: envs read the warning counters in mjData instead (a diverged episode is counted).
#ifndef JUGGLE_WORKER_MUJOCO_MODEL_H_
#define JUGGLE_WORKER_MUJOCO_MODEL_H_

#include <string>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"

namespace juggle {

// The caller owns the result (mj_deleteModel). INVALID_ARGUMENT "<where>: cannot load MJCF
// '<path>': <MuJoCo's error>".
absl::StatusOr<mjModel*> LoadModelXml(const std::string& path, const std::string& where);
// From mj_saveModel bytes. INVALID_ARGUMENT if MuJoCo cannot read them.
absl::StatusOr<mjModel*> LoadModelCompiled(const std::string& model_mjb);

}  // namespace juggle

#endif  // JUGGLE_WORKER_MUJOCO_MODEL_H_
