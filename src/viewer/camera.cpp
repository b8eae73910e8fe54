#include "viewer/camera.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <vector>

namespace freeform::viewer {
namespace {

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t pos = s.find(sep, start);
    out.push_back(s.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start));
    if (pos == std::string_view::npos) return out;
    start = pos + 1;
  }
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

double parse_number(std::string_view text, std::string_view key) {
  text = trim(text);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    throw InvalidInput("--camera: \"" + std::string(key) + "\" needs numbers, got \"" + std::string(text) + "\"");
  return value;
}

Eigen::Vector3d parse_vec3(std::string_view text, std::string_view key) {
  const auto parts = split(text, ',');
  if (parts.size() != 3)
    throw InvalidInput("--camera: \"" + std::string(key) + "\" needs three numbers x,y,z, got \"" + std::string(text) + "\"");
  return {parse_number(parts[0], key), parse_number(parts[1], key), parse_number(parts[2], key)};
}

}  // namespace

std::optional<ViewPreset> parse_view_preset(std::string_view name) {
  if (name == "front") return ViewPreset::Front;
  if (name == "back") return ViewPreset::Back;
  if (name == "left") return ViewPreset::Left;
  if (name == "right") return ViewPreset::Right;
  if (name == "top") return ViewPreset::Top;
  if (name == "bottom") return ViewPreset::Bottom;
  if (name == "iso") return ViewPreset::Iso;
  return std::nullopt;
}

namespace {
Eigen::Vector3d to_axis(const Eigen::Vector3d& v, UpAxis up) { return up == UpAxis::Z ? v : Eigen::Vector3d(v.x(), v.z(), -v.y()); }
Eigen::Vector3d z_up_direction(ViewPreset preset) {
  switch (preset) {
    case ViewPreset::Front: return {0, -1, 0};
    case ViewPreset::Back: return {0, 1, 0};
    case ViewPreset::Left: return {-1, 0, 0};
    case ViewPreset::Right: return {1, 0, 0};
    case ViewPreset::Top: return {0, 0, 1};
    case ViewPreset::Bottom: return {0, 0, -1};
    case ViewPreset::Iso: return Eigen::Vector3d(1, -1, 1).normalized();
  }
  return {0, -1, 0};
}
}  // namespace

Eigen::Vector3d preset_direction(ViewPreset preset, UpAxis up) { return to_axis(z_up_direction(preset), up); }

Eigen::Vector3d preset_up(ViewPreset preset, UpAxis up) {
  return to_axis(preset == ViewPreset::Top || preset == ViewPreset::Bottom ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(0, 0, 1), up);
}

Eigen::Matrix4d Camera::view() const {
  Eigen::Vector3d f = target - eye;
  if (f.norm() == 0.0) f = Eigen::Vector3d(0, 0, -1);
  f.normalize();
  Eigen::Vector3d s = f.cross(up);
  if (s.norm() < 1e-12 * std::max(1.0, up.norm())) s = f.cross(std::abs(f.z()) < 0.9 ? Eigen::Vector3d(0, 0, 1) : Eigen::Vector3d(0, 1, 0));
  s.normalize();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4d Camera::projection(double aspect) const {
  const double t = 1.0 / std::tan(0.5 * fov_y_deg * std::numbers::pi / 180.0);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = t / aspect;
  p(1, 1) = t;
  p(2, 2) = (z_far + z_near) / (z_near - z_far);
  p(2, 3) = 2.0 * z_far * z_near / (z_near - z_far);
  p(3, 2) = -1.0;
  return p;
}

void Camera::fit_clip_planes(const BoundingBox& box) {
  const double r = std::max(box.radius(), 1e-9);
  const double d = (box.center() - eye).norm();
  z_far = d + 1.5 * r;
  z_near = std::max(d - 1.5 * r, z_far * 1e-4);
}

Camera fit_view(const BoundingBox& box, ViewPreset preset, double aspect, double margin, UpAxis up_axis) {
  Camera c;
  const Eigen::Vector3d d = preset_direction(preset, up_axis);  // from the target towards the eye
  const Eigen::Vector3d s = (-d).cross(preset_up(preset, up_axis)).normalized(), u = s.cross(-d);
  const double tan_y = std::tan(0.5 * c.fov_y_deg * std::numbers::pi / 180.0), tan_x = tan_y * aspect;
  // Smallest eye distance at which every box corner is inside the frustum (shrunk by margin):
  // a corner at offset o from the centre is at depth D - o.d and needs |o.s| <= tan_x (D - o.d) / margin.
  double distance = 0.0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d p(i & 1 ? box.max.x() : box.min.x(), i & 2 ? box.max.y() : box.min.y(),
                            i & 4 ? box.max.z() : box.min.z());
    const Eigen::Vector3d o = p - box.center();
    distance = std::max({distance, o.dot(d) + margin * std::abs(o.dot(s)) / tan_x,
                         o.dot(d) + margin * std::abs(o.dot(u)) / tan_y});
  }
  distance = std::max(distance, 1e-6 * std::max(1.0, box.center().norm()));  // a point-like box
  c.target = box.center();
  c.eye = c.target + distance * d;
  c.up = preset_up(preset, up_axis);
  c.fit_clip_planes(box);
  return c;
}

Camera parse_camera_spec(std::string_view spec, const Camera& base) {
  Camera c = base;
  for (std::string_view item : split(spec, ';')) {
    item = trim(item);
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos)
      throw InvalidInput("--camera: expected key=value, got \"" + std::string(item) + "\" (keys: eye, target, up, fov)");
    const std::string_view key = trim(item.substr(0, eq)), value = item.substr(eq + 1);
    if (key == "eye") {
      c.eye = parse_vec3(value, key);
    } else if (key == "target") {
      c.target = parse_vec3(value, key);
    } else if (key == "up") {
      c.up = parse_vec3(value, key);
      if (c.up.norm() == 0.0) throw InvalidInput("--camera: \"up\" must not be the zero vector");
    } else if (key == "fov") {
      c.fov_y_deg = parse_number(value, key);
      if (!(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0)) throw InvalidInput("--camera: \"fov\" must be in (0, 180) degrees");
    } else {
      throw InvalidInput("--camera: unknown key \"" + std::string(key) + "\" (keys: eye, target, up, fov)");
    }
  }
  if ((c.eye - c.target).norm() == 0.0) throw InvalidInput("--camera: eye and target must differ");
  return c;
}

}  // namespace freeform::viewer
