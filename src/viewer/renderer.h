// OpenGL 3.3 core renderer of a RenderScene into the current framebuffer: smooth (or flat)
// shading with a headlight (two-sided), per-vertex colours, optional wireframe overlay. Needs a current
// 3.3 core context (EglContext headless, or the editor's window) for its whole lifetime.
// No algorithms here: geometry and colours come from render_scene.h / region_colors.h.
#pragma once

#include "viewer/camera.h"
#include "viewer/render_scene.h"

#include <cstdint>
#include <span>
#include <utility>

namespace freeform::viewer {

struct DrawOptions {
  Rgb background{1.0f, 1.0f, 1.0f};
  bool wireframe = false;
  // Flat: one normal per triangle (from screen-space derivatives of the position, so the
  // vertex normals are not used); default smooth: interpolated vertex normals.
  bool flat = false;
  // Lower-left corner of the viewport in the framebuffer (GL convention, pixels): the editor
  // draws right of its side panel. draw() still clears the whole framebuffer.
  int viewport_x = 0;
  int viewport_y = 0;
  Rgb wire_color{0.15f, 0.15f, 0.15f};
};

class Renderer {
 public:
  // Compiles the shaders; throws RenderError (gl_util.h) if they do not compile or link.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads all of the scene (buffers are reallocated).
  void upload(const RenderScene& scene);
  // Re-uploads positions and normals only (same vertex count): the editor's per-frame path.
  void update_geometry(const RenderScene& scene);
  // Only the vertex ranges (first, count) (GeometryPatch::ranges()): sub-buffer updates.
  void update_geometry(const RenderScene& scene, std::span<const std::pair<int, int>> ranges);
  // Re-uploads colours only (region changes).
  void update_colors(const RenderScene& scene);

  // Clears the bound framebuffer and draws into the width x height viewport at options.viewport_x/y.
  void draw(const Camera& camera, int width, int height, const DrawOptions& options = {}) const;

 private:
  std::uint32_t program_ = 0, vao_ = 0, vbo_position_ = 0, vbo_normal_ = 0, vbo_color_ = 0, ebo_ = 0;
  int loc_mvp_ = -1, loc_mv_ = -1, loc_light_ = -1, loc_wire_ = -1, loc_wire_color_ = -1, loc_flat_ = -1;
  int n_indices_ = 0, n_vertices_ = 0;
};

}  // namespace freeform::viewer
