// An OpenGL context for offscreen rendering on a machine without a display: EGL on Mesa's
// "surfaceless" platform (llvmpipe on the CPU when there is no GPU). No window, no surface: the
// context is made current with EGL_NO_SURFACE and MuJoCo renders into its own framebuffer.
//
// Thread-compatible: a context is current on one thread at a time (MakeCurrent()).
#ifndef JUGGLE_RENDER_GL_CONTEXT_H_
#define JUGGLE_RENDER_GL_CONTEXT_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace juggle {

class GlContext {
 public:
  // Creates a desktop-OpenGL context and makes it current on the calling thread. Sets
  // EGL_PLATFORM=surfaceless first unless the variable is already set. FAILED_PRECONDITION,
  // naming the Debian packages to install, when no EGL/GL provider works.
  static absl::StatusOr<std::unique_ptr<GlContext>> Create();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread. INTERNAL if EGL refuses.
  absl::Status MakeCurrent();

  // GL_RENDERER and GL_VERSION strings, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }

 private:
  GlContext() = default;

  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string renderer_;
  std::string version_;
};

}  // namespace juggle

#endif  // JUGGLE_RENDER_GL_CONTEXT_H_
