#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "absl/strings/str_cat.h"

namespace juggle {

absl::StatusOr<std::unique_ptr<Renderer>> Renderer::Create(const mjModel* model,
                                                           const RenderOptions& options) {
  constexpr int kMaxSize = 8192;
  if (options.width <= 0 || options.height <= 0 || options.width > kMaxSize ||
      options.height > kMaxSize) {
    return absl::InvalidArgumentError(absl::StrCat("image size must be in 1..", kMaxSize,
                                                   ", got ", options.width, "x",
                                                   options.height));
  }
  absl::StatusOr<std::unique_ptr<GlContext>> gl = GlContext::Create();
  if (!gl.ok()) return gl.status();
  mjModel* copy = mj_copyModel(nullptr, model);
  if (copy == nullptr) return absl::InternalError("mj_copyModel failed");
  // The offscreen framebuffer is sized from the model's <visual><global>; MSAA samples too.
  copy->vis.global.offwidth = options.width;
  copy->vis.global.offheight = options.height;
  copy->vis.quality.offsamples = options.high_quality ? 4 : 0;
  std::unique_ptr<Renderer> renderer(new Renderer(*std::move(gl), copy, options));
  // Warm-up: llvmpipe's first frame differs from later renders of the same state by ±1 in a few
  // textured pixels (measured); one throwaway frame makes every returned frame reproducible.
  mjData* warm = mj_makeData(copy);
  mj_forward(copy, warm);
  Image discard;
  const absl::Status status = renderer->Render(warm, "", "", &discard);
  mj_deleteData(warm);
  if (!status.ok()) return status;
  return renderer;
}

Renderer::Renderer(std::unique_ptr<GlContext> gl, mjModel* model, const RenderOptions& options)
    : gl_(std::move(gl)), model_(model), options_(options) {
  mjv_defaultCamera(&camera_);
  camera_.type = mjCAMERA_FREE;
  camera_.azimuth = options_.azimuth;
  camera_.elevation = options_.elevation;
  camera_.distance = options_.distance;
  mjv_defaultOption(&vis_options_);
  mjv_defaultScene(&scene_);
  mjv_makeScene(model_, &scene_, 2000);
  scene_.flags[mjRND_SHADOW] = options_.high_quality;
  scene_.flags[mjRND_REFLECTION] = options_.high_quality;
  mjr_defaultContext(&context_);
  mjr_makeContext(model_, &context_, options_.font_scale);
  mjr_setBuffer(mjFB_OFFSCREEN, &context_);
}

void Renderer::FitHeight(double top) {
  // The frame shows up to the look-at height plus the distance times the tangent of half
  // MuJoCo's vertical field of view (a tenth kept spare); `top` gets a 0.2 m margin.
  const double tan_half_fovy = std::tan(0.5 * model_->vis.global.fovy * mjPI / 180.0);
  const double wanted = top + 0.2;
  if (wanted <= options_.lookat_height + options_.distance * tan_half_fovy / 1.1) return;
  options_.lookat_height = std::max(options_.lookat_height, 0.5 * wanted);
  options_.distance =
      std::max(options_.distance, 1.1 * (wanted - options_.lookat_height) / tan_half_fovy);
  camera_.distance = options_.distance;
}

Renderer::~Renderer() {
  gl_->MakeCurrent().IgnoreError();
  mjr_freeContext(&context_);
  mjv_freeScene(&scene_);
  mj_deleteModel(model_);
}

absl::Status Renderer::Render(const mjData* data, const std::string& labels,
                              const std::string& values, Image* out) {
  if (absl::Status s = gl_->MakeCurrent(); !s.ok()) return s;
  if (context_.currentBuffer != mjFB_OFFSCREEN) {
    mjr_setBuffer(mjFB_OFFSCREEN, &context_);
    if (context_.currentBuffer != mjFB_OFFSCREEN) {
      return absl::InternalError("MuJoCo offscreen framebuffer is not available");
    }
  }
  if (options_.track_body >= 0) {
    const double* p = data->xpos + 3 * options_.track_body;
    camera_.lookat[0] = p[0];
    camera_.lookat[1] = p[1];
  }
  camera_.lookat[2] = options_.lookat_height;

  const mjrRect viewport = {0, 0, options_.width, options_.height};
  // mjv_updateScene takes non-const data (it may run mj_forward-like updates for perturbations,
  // which are off here); it only reads positions.
  mjv_updateScene(model_, const_cast<mjData*>(data), &vis_options_, nullptr, &camera_, mjCAT_ALL,
                  &scene_);
  mjr_render(viewport, &scene_, &context_);
  if (!labels.empty() || !values.empty()) {
    mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, labels.c_str(), values.c_str(),
                &context_);
  }
  const size_t stride = static_cast<size_t>(options_.width) * 3;
  flipped_.resize(stride * options_.height);
  mjr_readPixels(flipped_.data(), nullptr, viewport, &context_);
  out->Resize(options_.width, options_.height);
  for (int y = 0; y < options_.height; ++y) {
    std::memcpy(&out->rgb[y * stride], &flipped_[(options_.height - 1 - y) * stride], stride);
  }
  return absl::OkStatus();
}

}  // namespace juggle
