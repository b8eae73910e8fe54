#include "viewer/gl_util.h"

#include <cstdio>

namespace freeform::viewer {

void check_gl(const char* what) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(e));
  throw RenderError(std::string(what) + ": OpenGL error " + code);
}

}  // namespace freeform::viewer
