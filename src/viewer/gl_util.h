// GL function declarations (GLVND libOpenGL exports the core entry points) and the error type
// of the viewer library. Include this instead of <GL/gl.h>.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>

#include "freeform/common/error.h"

#include <string>

namespace freeform::viewer {

// No usable OpenGL/EGL, or a GL call failed. The CLI reports it and writes nothing.
class RenderError : public Error {
 public:
  using Error::Error;
};

// Throws RenderError("WHAT: GL error 0x....") if glGetError() reports an error.
void check_gl(const char* what);

}  // namespace freeform::viewer
