#include "viewer/offscreen.h"

#include "viewer/gl_util.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace freeform::viewer {

OffscreenTarget::OffscreenTarget(int width, int height, int samples) : width_(width), height_(height) {
  GLint max_size = 0, max_samples = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (width < 1 || height < 1 || width > max_size || height > max_size)
    throw RenderError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                      " is outside 1.." + std::to_string(max_size));
  samples_ = std::clamp(samples, 0, static_cast<int>(max_samples));
  if (samples_ == 1) samples_ = 0;

  glGenFramebuffers(1, &fbo_);
  glGenRenderbuffers(1, &color_);
  glGenRenderbuffers(1, &depth_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glBindRenderbuffer(GL_RENDERBUFFER, color_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);

  glGenFramebuffers(1, &resolve_fbo_);
  glGenRenderbuffers(1, &resolve_color_);
  glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
  glBindRenderbuffer(GL_RENDERBUFFER, resolve_color_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color_);
  const GLenum resolve_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE || resolve_status != GL_FRAMEBUFFER_COMPLETE) {
    this->~OffscreenTarget();
    throw RenderError("offscreen framebuffer incomplete");
  }
  check_gl("offscreen framebuffer");
}

OffscreenTarget::~OffscreenTarget() {
  const GLuint fbos[2] = {fbo_, resolve_fbo_};
  const GLuint rbs[3] = {color_, depth_, resolve_color_};
  glDeleteFramebuffers(2, fbos);
  glDeleteRenderbuffers(3, rbs);
  fbo_ = resolve_fbo_ = color_ = depth_ = resolve_color_ = 0;
}

void OffscreenTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, fbo_); }

std::vector<std::uint8_t> OffscreenTarget::read_rgba() const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  std::vector<std::uint8_t> pixels(row * static_cast<std::size_t>(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);  // stays bound: draw again, read again
  check_gl("readback");
  std::vector<std::uint8_t> top_first(pixels.size());  // GL rows start at the bottom
  for (int y = 0; y < height_; ++y)
    std::memcpy(top_first.data() + static_cast<std::size_t>(y) * row,
                pixels.data() + static_cast<std::size_t>(height_ - 1 - y) * row, row);
  return top_first;
}

}  // namespace freeform::viewer
