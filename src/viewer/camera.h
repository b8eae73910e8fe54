// GL-free camera: a look-at camera with a perspective projection, the standard view presets,
// fitting the view to a bounding box, and the --camera text syntax of `freeform render`
// (docs/render.md). Used by the headless renderer and by the editor (orbit/zoom change
// eye/target/up; the renderer only reads view() and projection()).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <string_view>

namespace freeform::viewer {

struct BoundingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d center() const { return 0.5 * (min + max); }
  double radius() const { return 0.5 * (max - min).norm(); }  // of the circumscribed sphere
};

enum class ViewPreset { Front, Back, Left, Right, Top, Bottom, Iso };
// Which world axis is "up" for the presets. Many scanned meshes (the armadillo) are y-up.
enum class UpAxis { Z, Y };

// "front", "back", "left", "right", "top", "bottom", "iso"; nullopt for anything else.
std::optional<ViewPreset> parse_view_preset(std::string_view name);

// Unit vector from the target towards the eye of a preset. z up (y away from the viewer in the
// front view): front -y, back +y, left -x, right +x, top +z, bottom -z, iso (1,-1,1)/sqrt 3.
// y up (the viewer on +z in the front view): the same frame mapped by (x, y, z) -> (x, z, -y).
Eigen::Vector3d preset_direction(ViewPreset preset, UpAxis up = UpAxis::Z);
// The up vector on screen: the up axis, except top and bottom (z up: +y; y up: -z).
Eigen::Vector3d preset_up(ViewPreset preset, UpAxis up = UpAxis::Z);

struct Camera {
  Eigen::Vector3d eye{0, -3, 0};
  Eigen::Vector3d target{0, 0, 0};
  Eigen::Vector3d up{0, 0, 1};
  double fov_y_deg = 30.0;  // vertical field of view
  double z_near = 0.01;
  double z_far = 100.0;

  // World -> eye (OpenGL convention: the camera looks down -z). up need not be orthogonal
  // to the view direction but must not be parallel to it (then a perpendicular is chosen).
  Eigen::Matrix4d view() const;
  // Eye -> clip, symmetric perspective frustum; aspect = width / height.
  Eigen::Matrix4d projection(double aspect) const;
  // Near/far planes that enclose the box with a margin (call after moving the camera).
  void fit_clip_planes(const BoundingBox& box);
};

// A camera looking at the box centre along the preset direction, at the smallest distance at
// which all eight box corners are inside the view shrunk by 1/margin (margin >= 1: room).
Camera fit_view(const BoundingBox& box, ViewPreset preset, double aspect, double margin = 1.08, UpAxis up = UpAxis::Z);

// Parses "eye=x,y,z;target=x,y,z;up=x,y,z;fov=deg" (any subset, any order; missing keys are
// taken from `base`, so a preset fitted to the mesh can be adjusted). Throws
// freeform::InvalidInput naming the bad key or value.
Camera parse_camera_spec(std::string_view spec, const Camera& base);

}  // namespace freeform::viewer
