#include "viewer/egl_context.h"

#include "viewer/gl_util.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <vector>

namespace freeform::viewer {
namespace {

std::string egl_error() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04x", static_cast<unsigned>(eglGetError()));
  return buf;
}

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// Initializes `dpy`; returns false (and terminates it) if it has no 3.3 core context.
EGLContext try_context(EGLDisplay dpy, std::string& why) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor)) {
    why += " eglInitialize failed (" + egl_error() + ");";
    return EGL_NO_CONTEXT;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why += " no desktop OpenGL API;";
    eglTerminate(dpy);
    return EGL_NO_CONTEXT;
  }
  EGLConfig config = nullptr;
  const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
  if (!has_extension(ext, "EGL_KHR_no_config_context")) {
    const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(dpy, attribs, &config, 1, &n) || n < 1) {
      why += " no OpenGL config;";
      eglTerminate(dpy);
      return EGL_NO_CONTEXT;
    }
  }
  if (!has_extension(ext, "EGL_KHR_surfaceless_context")) {
    why += " no EGL_KHR_surfaceless_context;";
    eglTerminate(dpy);
    return EGL_NO_CONTEXT;
  }
  const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attribs);
  if (ctx == EGL_NO_CONTEXT) {
    why += " no OpenGL 3.3 core context (" + egl_error() + ");";
    eglTerminate(dpy);
  }
  return ctx;
}

}  // namespace

EglContext::EglContext() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client == nullptr)
    throw RenderError("no EGL: the EGL library has no client extensions (" + egl_error() +
                      "); install libegl1 and libegl-mesa0 (scripts/bootstrap.sh)");
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr || !has_extension(client, "EGL_EXT_platform_base"))
    throw RenderError("EGL lacks EGL_EXT_platform_base: cannot open a headless display");

  std::string why;
  std::vector<std::pair<EGLDisplay, std::string>> candidates;
  if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY) candidates.emplace_back(d, "surfaceless");
    else why += " surfaceless platform: no display;";
  } else {
    why += " no EGL_MESA_platform_surfaceless;";
  }
  if (has_extension(client, "EGL_EXT_platform_device")) {
    const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT devices[16];
    EGLint n = 0;
    if (query_devices != nullptr && query_devices(16, devices, &n))
      for (EGLint i = 0; i < n; ++i) {
        EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY) candidates.emplace_back(d, "device " + std::to_string(i));
      }
    if (n == 0) why += " no EGL devices;";
  }
  for (const auto& [dpy, name] : candidates) {
    std::string reason;
    EGLContext ctx = try_context(dpy, reason);
    if (ctx == EGL_NO_CONTEXT) {
      why += " " + name + ":" + reason;
      continue;
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
      why += " " + name + ": eglMakeCurrent failed (" + egl_error() + ");";
      eglDestroyContext(dpy, ctx);
      eglTerminate(dpy);
      continue;
    }
    display_ = dpy;
    context_ = ctx;
    const auto str = [](GLenum e) {
      const auto* s = reinterpret_cast<const char*>(glGetString(e));
      return std::string(s ? s : "?");
    };
    description_ = name + ": " + str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION);
    return;
  }
  throw RenderError("no headless OpenGL 3.3 context via EGL:" + why +
                    " (Mesa's EGL and llvmpipe come with libegl-mesa0 and libgl1-mesa-dri; scripts/bootstrap.sh)");
}

EglContext::~EglContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

void EglContext::make_current() const {
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw RenderError("eglMakeCurrent failed (" + egl_error() + ")");
}

}  // namespace freeform::viewer
