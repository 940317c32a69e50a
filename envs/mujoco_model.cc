#include "envs/mujoco_model.h"

#include <cstring>
#include <mutex>
#include <memory>

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

// Stateless, hence safe from every thread.
void SilentWarning(const char*) {}

// MuJoCo's warning hook is a process-wide global: set it once, not from every loading thread
// (workers of one process load models concurrently; ThreadSanitizer found the racing writes).
void SilenceMujocoWarningsOnce() {
  static std::once_flag once;
  std::call_once(once, [] { mju_user_warning = SilentWarning; });
}

}  // namespace

absl::StatusOr<MjModelPtr> LoadModelXml(const std::string& path, const std::string& where) {
  SilenceMujocoWarningsOnce();
  char error[1024] = "";
  MjModelPtr model(mj_loadXML(path.c_str(), nullptr, error, sizeof(error)));
  if (model == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": cannot load MJCF '", path, "': ", error));
  }
  return model;
}

absl::StatusOr<MjModelPtr> LoadModelCompiled(const std::string& model_mjb) {
  SilenceMujocoWarningsOnce();
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* kName = "model.mjb";
  if (mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(model_mjb.size())) != 0) {
    return absl::InternalError("cannot allocate the model in MuJoCo's virtual file system");
  }
  const int index = mj_findFileVFS(vfs.get(), kName);
  std::memcpy(vfs->filedata[index], model_mjb.data(), model_mjb.size());
  MjModelPtr model(mj_loadModel(kName, vfs.get()));
  mj_deleteVFS(vfs.get());
  if (model == nullptr) return absl::InvalidArgumentError("cannot load the compiled model");
  return model;
}

std::string SaveModel(const mjModel* model) {
  std::string bytes(mj_sizeModel(model), '\0');
  mj_saveModel(model, nullptr, bytes.data(), static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace juggle
