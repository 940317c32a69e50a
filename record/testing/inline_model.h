// Tests only: a MuJoCo model compiled from MJCF text held in the test (no files), owned by a
// unique_ptr. A compile error fails the calling test and returns null.
#ifndef JUGGLE_RECORD_TESTING_INLINE_MODEL_H_
#define JUGGLE_RECORD_TESTING_INLINE_MODEL_H_

#include <cstring>
#include <memory>
#include <string>

#include <mujoco/mujoco.h>

#include "gtest/gtest.h"

namespace juggle::testing {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using InlineModel = std::unique_ptr<mjModel, ModelDeleter>;

inline InlineModel LoadInlineModel(const std::string& mjcf) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "model.xml", static_cast<int>(mjcf.size()));
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "model.xml")], mjcf.data(), mjcf.size());
  char error[512] = "";
  mjModel* m = mj_loadXML("model.xml", &vfs, error, sizeof(error));
  mj_deleteVFS(&vfs);
  EXPECT_NE(m, nullptr) << error;
  return InlineModel(m);
}

}  // namespace juggle::testing

#endif  // JUGGLE_RECORD_TESTING_INLINE_MODEL_H_
