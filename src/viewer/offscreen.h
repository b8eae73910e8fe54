// An offscreen framebuffer (multisampled colour + depth, resolved on readback) in the current
// GL context, and reading it back as RGBA8 rows top to bottom.
#pragma once

#include <cstdint>
#include <vector>

namespace freeform::viewer {

class OffscreenTarget {
 public:
  // width, height >= 1 and within GL_MAX_RENDERBUFFER_SIZE; samples is clamped to
  // GL_MAX_SAMPLES (0 or 1: no multisampling). Throws RenderError if incomplete.
  OffscreenTarget(int width, int height, int samples = 4);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  void bind() const;  // draw into it (Renderer::draw)
  // Resolves and reads the pixels: width*height*4 bytes, first row = top of the image.
  // Leaves this target bound for drawing.
  std::vector<std::uint8_t> read_rgba() const;

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }

 private:
  int width_, height_, samples_ = 0;
  std::uint32_t fbo_ = 0, color_ = 0, depth_ = 0;            // drawn into (maybe multisampled)
  std::uint32_t resolve_fbo_ = 0, resolve_color_ = 0;        // single-sampled, for readback
};

// Encodes RGBA8 rows (top first) as PNG in memory (stb_image_write).
std::vector<std::uint8_t> encode_png(const std::vector<std::uint8_t>& rgba, int width, int height);

}  // namespace freeform::viewer
