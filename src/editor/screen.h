// The screen a camera sees (GL-free): projection of world points to pixels and rays through
// pixels. Pixel coordinates are GLFW/ImGui's: x right, y down, origin at the top-left corner
// of the viewport, (0.5, 0.5) the centre of the first pixel. Shared by picking, the gizmo and
// the modal transform tools.
#pragma once

#include "viewer/camera.h"

#include "freeform/mesh/types.h"

#include <Eigen/Core>

#include <optional>

namespace freeform::editor {

struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();  // unit length
};

struct ScreenView {
  viewer::Camera camera;
  int width = 1;   // viewport size in pixels (> 0)
  int height = 1;

  double aspect() const { return static_cast<double>(width) / static_cast<double>(height); }
  Eigen::Matrix4d view_projection() const;
  // Pixel position (x, y) and NDC depth z in [-1, 1] of a world point; nullopt if the point is
  // not in front of the eye (w <= 0).
  std::optional<Eigen::Vector3d> project(const Vec3& p) const;
  // The ray from the eye through a pixel position.
  Ray ray(const Eigen::Vector2d& pixel) const;
  // Unit vector from the eye towards the target.
  Vec3 forward() const;
  // World length of one pixel at the depth of p (for screen-constant gizmo sizes and drags).
  double world_per_pixel(const Vec3& p) const;
};

}  // namespace freeform::editor
