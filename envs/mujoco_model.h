// Loading MuJoCo models for every env family: from MJCF (the learner, tools) or from the
// compiled bytes the learner ships to workers; owning pointers for mjModel and mjData. Also
// silences MuJoCo's process-global warning handler: envs read the warning counters in mjData
// instead (a diverged episode is counted).
#ifndef JUGGLE_ENVS_MUJOCO_MODEL_H_
#define JUGGLE_ENVS_MUJOCO_MODEL_H_

#include <memory>
#include <string>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"

namespace juggle {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

// INVALID_ARGUMENT "<where>: cannot load MJCF '<path>': <MuJoCo's error>".
absl::StatusOr<MjModelPtr> LoadModelXml(const std::string& path, const std::string& where);
// From mj_saveModel bytes. INVALID_ARGUMENT if MuJoCo cannot read them.
absl::StatusOr<MjModelPtr> LoadModelCompiled(const std::string& model_mjb);
// mj_saveModel bytes of `model` (what the learner ships to workers).
std::string SaveModel(const mjModel* model);

}  // namespace juggle

#endif  // JUGGLE_ENVS_MUJOCO_MODEL_H_
