// Offscreen renderer for the juggling scene: MuJoCo's mjv_/mjr_ pipeline on an EGL context
// (render/gl_context.h), a camera whose look-at point follows one body (the character's root),
// and a two-column caption drawn with mjr_overlay.
//
// Thread-compatible: one thread at a time (the GL context is made current on every call).
#ifndef JUGGLE_RENDER_RENDERER_H_
#define JUGGLE_RENDER_RENDERER_H_

#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "render/gl_context.h"
#include "render/image.h"

namespace juggle {

struct RenderOptions {
  int width = 640;
  int height = 480;
  // false: no shadows, no reflections, no multisampling (≈ 10× faster on llvmpipe).
  bool high_quality = false;
  // Body whose world x, y the camera looks at (at `lookat_height`); -1: the world origin.
  int track_body = -1;
  double lookat_height = 0.8;  // m
  // Camera: degrees about z (90 looks along +y, from the character's right side), degrees
  // of elevation (negative looks down), metres from the look-at point.
  double azimuth = 115;
  double elevation = -10;
  double distance = 3.0;
  int font_scale = mjFONTSCALE_150;
};

class Renderer {
 public:
  // Creates a GL context and MuJoCo's render context for `model` (copied: the copy's offscreen
  // buffer size and multisampling are set from `options`; `model` may be freed afterwards).
  // FAILED_PRECONDITION (naming the packages to install) without a working GL provider;
  // INVALID_ARGUMENT for a non-positive or oversized (> 8192) width or height.
  static absl::StatusOr<std::unique_ptr<Renderer>> Create(const mjModel* model,
                                                          const RenderOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders the positions in `data` (REQUIRES: mj_forward or mj_kinematics has run on them,
  // and `data` belongs to a model with the same sizes) with `labels`/`values` as the caption
  // (newline-separated columns; both empty: no caption). `out` is resized to width × height.
  absl::Status Render(const mjData* data, const std::string& labels, const std::string& values,
                      Image* out);

  // When `top` (m, plus a margin) is above what the frame shows, raises the look-at point and
  // backs the camera off so that the floor to `top` fits the vertical field of view; never
  // lower or closer than the options'. render_job.cc calls it with a recording's highest ball.
  void FitHeight(double top);

  const RenderOptions& options() const { return options_; }
  // The GL renderer string, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& gl_renderer() const { return gl_->renderer(); }

 private:
  Renderer(std::unique_ptr<GlContext> gl, mjModel* model, const RenderOptions& options);

  std::unique_ptr<GlContext> gl_;
  mjModel* model_;  // owned copy
  RenderOptions options_;
  mjvCamera camera_;
  mjvOption vis_options_;
  mjvScene scene_;
  mjrContext context_;
  std::vector<unsigned char> flipped_;  // bottom-up rows from mjr_readPixels
};

}  // namespace juggle

#endif  // JUGGLE_RENDER_RENDERER_H_
