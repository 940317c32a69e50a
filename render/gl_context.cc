#include "render/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle {
namespace {

constexpr char kInstallHint[] =
    "offscreen rendering needs EGL and Mesa's software rasteriser: "
    "apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 "
    "(scripts/dev/install_deps.sh installs them)";

std::string EglError(const char* what) {
  return absl::StrFormat("%s failed (EGL error 0x%04x)", what, eglGetError());
}

// GL entry points are looked up at run time: only MuJoCo calls GL, so the headers of a GL
// loader are not needed here.
using GetStringFn = const unsigned char* (*)(unsigned int);
constexpr unsigned int kGlRenderer = 0x1F01;
constexpr unsigned int kGlVersion = 0x1F02;

EGLDisplay OpenDisplay() {
  EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (display != EGL_NO_DISPLAY) return display;
  // Fallback: ask for the surfaceless platform explicitly (EGL_MESA_platform_surfaceless).
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) return EGL_NO_DISPLAY;
  return get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
}

}  // namespace

absl::StatusOr<std::unique_ptr<GlContext>> GlContext::Create() {
  // Mesa picks the platform from EGL_PLATFORM; without a display server only "surfaceless"
  // works (as MuJoCo's MUJOCO_GL=egl rendering documents). A user's explicit choice is kept.
  setenv("EGL_PLATFORM", "surfaceless", /*overwrite=*/0);

  EGLDisplay display = OpenDisplay();
  if (display == EGL_NO_DISPLAY) {
    return absl::FailedPreconditionError(absl::StrCat(
        "no GL provider found: ", EglError("eglGetDisplay"), "; ", kInstallHint));
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    const std::string platform = std::getenv("EGL_PLATFORM");
    return absl::FailedPreconditionError(absl::StrCat(
        "no GL provider found: ", EglError("eglInitialize"), " with EGL_PLATFORM=", platform,
        platform == "surfaceless" ? "" : " (without a display server use surfaceless)", "; ",
        kInstallHint));
  }
  // EGL_SURFACE_TYPE defaults to EGL_WINDOW_BIT, which the surfaceless platform never
  // offers: ask for pbuffer configs (as MuJoCo's record.cc does), then for any (mask 0).
  EGLConfig config;
  EGLint num_configs = 0;
  for (EGLint surface_type : {EGL_PBUFFER_BIT, 0}) {
    const EGLint config_attribs[] = {EGL_RED_SIZE,          8,
                                     EGL_GREEN_SIZE,        8,
                                     EGL_BLUE_SIZE,         8,
                                     EGL_ALPHA_SIZE,        8,
                                     EGL_DEPTH_SIZE,        24,
                                     EGL_STENCIL_SIZE,      8,
                                     EGL_COLOR_BUFFER_TYPE, EGL_RGB_BUFFER,
                                     EGL_RENDERABLE_TYPE,   EGL_OPENGL_BIT,
                                     EGL_SURFACE_TYPE,      surface_type,
                                     EGL_NONE};
    if (eglChooseConfig(display, config_attribs, &config, 1, &num_configs) && num_configs > 0) {
      break;
    }
  }
  if (num_configs < 1) {
    return absl::FailedPreconditionError(absl::StrCat(
        "no EGL config with desktop OpenGL and RGBA8/depth24/stencil8 (",
        EglError("eglChooseConfig"), "); ", kInstallHint));
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    return absl::FailedPreconditionError(
        absl::StrCat(EglError("eglBindAPI(EGL_OPENGL_API)"), "; ", kInstallHint));
  }
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
  if (context == EGL_NO_CONTEXT) {
    return absl::FailedPreconditionError(
        absl::StrCat(EglError("eglCreateContext"), "; ", kInstallHint));
  }
  std::unique_ptr<GlContext> gl(new GlContext());
  gl->display_ = display;
  gl->context_ = context;
  if (absl::Status s = gl->MakeCurrent(); !s.ok()) return s;

  auto get_string = reinterpret_cast<GetStringFn>(eglGetProcAddress("glGetString"));
  if (get_string == nullptr || get_string(kGlVersion) == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat("EGL context has no working glGetString; ", kInstallHint));
  }
  gl->renderer_ = reinterpret_cast<const char*>(get_string(kGlRenderer));
  gl->version_ = reinterpret_cast<const char*>(get_string(kGlVersion));
  return gl;
}

GlContext::~GlContext() {
  if (context_ != nullptr) {
    if (eglGetCurrentContext() == context_) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display_, context_);
  }
  // The display is process-wide and may serve other contexts: it is not terminated.
}

absl::Status GlContext::MakeCurrent() {
  if (eglGetCurrentContext() == context_) return absl::OkStatus();
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    return absl::InternalError(EglError("eglMakeCurrent"));
  }
  return absl::OkStatus();
}

}  // namespace juggle
