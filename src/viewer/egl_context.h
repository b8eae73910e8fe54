// A headless OpenGL 3.3 core context through EGL: no display, no X server, no window.
// Tries the Mesa surfaceless platform (EGL_MESA_platform_surfaceless) first, then every device
// of the EGL device platform (EGL_EXT_platform_device). The context is current on the
// creating thread without a surface: render into an OffscreenTarget.
#pragma once

#include <string>

namespace freeform::viewer {

class EglContext {
 public:
  // Throws RenderError saying what is missing (EGL library, platform, 3.3 core context).
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  void make_current() const;
  // e.g. "surfaceless: llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  const std::string& description() const { return description_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string description_;
};

}  // namespace freeform::viewer
