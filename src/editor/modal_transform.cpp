#include "editor/modal_transform.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace freeform::editor {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
constexpr std::size_t kMaxTyped = 32;

// Where the mouse ray meets the plane through `point` with normal `normal` (in front of the eye).
std::optional<Vec3> hit_plane(const ScreenView& view, const Eigen::Vector2d& mouse, const Vec3& point,
                              const Vec3& normal) {
  const Ray r = view.ray(mouse);
  const double denom = r.direction.dot(normal);
  if (std::abs(denom) < 1e-12) return std::nullopt;
  const double u = (point - r.origin).dot(normal) / denom;
  if (!(u > 0.0)) return std::nullopt;
  return r.origin + u * r.direction;
}

// Parameter s of the point c + s a (a unit) under the mouse, after snapping the mouse to the
// projected axis: the ray through the snapped pixel meets the axis line there.
std::optional<double> axis_parameter(const ScreenView& view, const Eigen::Vector2d& mouse, const Vec3& c,
                                     const Vec3& a) {
  const auto p0 = view.project(c);
  if (!p0) return std::nullopt;
  const double h = 10.0 * view.world_per_pixel(c);
  auto p1 = view.project(c + h * a);
  double sign = 1.0;
  if (!p1) p1 = view.project(c - h * a), sign = -1.0;
  if (!p1) return std::nullopt;
  Eigen::Vector2d d2 = sign * (p1->head<2>() - p0->head<2>());
  if (d2.norm() < 1e-6) return std::nullopt;  // the axis points at the eye
  d2.normalize();
  const Eigen::Vector2d q = p0->head<2>() + (mouse - p0->head<2>()).dot(d2) * d2;
  const Ray r = view.ray(q);
  // Closest points of eye + u r and c + s a (both unit): they meet, up to round-off.
  const Vec3 w0 = r.origin - c;
  const double b = r.direction.dot(a), d = r.direction.dot(w0), e = a.dot(w0);
  const double denom = 1.0 - b * b;
  if (denom < 1e-12) return std::nullopt;
  const double u = (b * e - d) / denom;
  if (!(u > 0.0)) return std::nullopt;  // beyond the vanishing point
  return (e - b * d) / denom;
}

double clamp_factor(double f) {
  if (std::abs(f) >= 1e-6) return f;
  return f < 0.0 ? -1e-6 : 1e-6;
}

std::string format_number(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v == 0.0 ? 0.0 : v);  // no "-0"
  return buf;
}

}  // namespace

int axis_index(AxisLock lock) {
  switch (lock) {
    case AxisLock::GlobalX:
    case AxisLock::LocalX:
      return 0;
    case AxisLock::GlobalY:
    case AxisLock::LocalY:
      return 1;
    case AxisLock::GlobalZ:
    case AxisLock::LocalZ:
      return 2;
    case AxisLock::None:
      break;
  }
  return -1;
}

bool is_local(AxisLock lock) {
  return lock == AxisLock::LocalX || lock == AxisLock::LocalY || lock == AxisLock::LocalZ;
}

ModalTransform::ModalTransform(TransformKind kind, const Manipulator& start, const Vec3& pivot, const ScreenView& view,
                               const Eigen::Vector2d& mouse)
    : kind_(kind), start_(start), pivot_(pivot), view_(view), mouse_start_(mouse), mouse_(mouse), sweep_ref_(mouse) {
  if (!start.translation.allFinite() || !start.rotation.coeffs().allFinite() || !start.scale.allFinite() ||
      !pivot.allFinite() || !mouse.allFinite())
    throw InvalidInput("modal transform: the manipulator, pivot and mouse position must be finite");
  if (!(start.rotation.norm() > 1e-12))
    throw InvalidInput("modal transform: the manipulator rotation is a zero quaternion; use the identity");
  r0_ = start.rotation.normalized().toRotationMatrix();
  c0_ = pivot + start.translation;
}

void ModalTransform::press_axis(int axis) {
  if (axis < 0 || axis > 2) throw InvalidInput("modal transform: axis must be 0 (X), 1 (Y) or 2 (Z)");
  static constexpr AxisLock global[3] = {AxisLock::GlobalX, AxisLock::GlobalY, AxisLock::GlobalZ};
  static constexpr AxisLock local[3] = {AxisLock::LocalX, AxisLock::LocalY, AxisLock::LocalZ};
  AxisLock next = global[axis];
  if (lock_ == global[axis])
    next = local[axis];
  else if (lock_ == local[axis])
    next = AxisLock::None;
  set_axis(next);
}

void ModalTransform::set_axis(AxisLock lock) {
  if (kind_ == TransformKind::Scale && lock != AxisLock::None && !is_local(lock))
    lock = static_cast<AxisLock>(static_cast<int>(AxisLock::LocalX) + axis_index(lock));
  lock_ = lock;
  grab_ = Vec3::Zero();  // a new axis: the last valid amount of the old one is meaningless
  update_mouse_amount();
}

bool ModalTransform::type_char(char c) {
  if (c == '-') {
    if (!typed_text_.empty() && typed_text_.front() == '-')
      typed_text_.erase(0, 1);
    else
      typed_text_.insert(typed_text_.begin(), '-');
    return true;
  }
  const bool digit = c >= '0' && c <= '9';
  if (!digit && c != '.') return false;
  if (c == '.' && typed_text_.find('.') != std::string::npos) return false;
  if (typed_text_.size() >= kMaxTyped) return false;
  typed_text_.push_back(c);
  return true;
}

void ModalTransform::backspace() {
  if (typed_text_.empty()) return;
  if (typed_text_.size() > 1 || typed_text_.front() != '-')
    typed_text_.pop_back();
  else
    typed_text_.clear();  // only the sign is left
}

std::optional<double> ModalTransform::typed_value() const {
  const bool negative = !typed_text_.empty() && typed_text_.front() == '-';
  const std::string digits = negative ? typed_text_.substr(1) : typed_text_;
  if (digits.find_first_of("0123456789") == std::string::npos) return std::nullopt;  // "", "."
  const double v = std::strtod(digits.c_str(), nullptr);
  if (!std::isfinite(v)) return std::nullopt;
  return negative ? -v : v;
}

void ModalTransform::move_mouse(const Eigen::Vector2d& mouse) {
  if (!mouse.allFinite()) return;
  mouse_ = mouse;
  update_mouse_amount();
}

void ModalTransform::set_view(const ScreenView& view) {
  view_ = view;
  grab_ = Vec3::Zero();
  update_mouse_amount();
}

Vec3 ModalTransform::axis_vector() const {
  const int i = axis_index(lock_);
  if (i < 0) return Vec3::UnitX();
  return is_local(lock_) ? Vec3(r0_.col(i)) : Vec3(Vec3::Unit(i));
}

void ModalTransform::update_mouse_amount() {
  if (kind_ == TransformKind::Grab) {
    update_grab();
  } else if (kind_ == TransformKind::Rotate) {
    const auto c = view_.project(c0_);
    if (!c) return;
    const Eigen::Vector2d a = sweep_ref_ - c->head<2>(), b = mouse_ - c->head<2>();
    if (b.norm() < 1e-9) return;  // at the centre: no direction yet
    if (a.norm() >= 1e-9) {
      // Counter-clockwise as seen: pixel y points down, so flip it.
      const double cross = a.x() * -b.y() - -a.y() * b.x();
      sweep_ += std::atan2(cross, a.dot(b));
    }
    sweep_ref_ = mouse_;
  }
  // Scale reads the mouse directly in scale_factor().
}

void ModalTransform::update_grab() {
  if (lock_ == AxisLock::None) {
    const Vec3 n = view_.forward();
    const auto h0 = hit_plane(view_, mouse_start_, c0_, n), h = hit_plane(view_, mouse_, c0_, n);
    if (h0 && h) grab_ = *h - *h0;
    return;
  }
  const Vec3 a = axis_vector();
  const auto s0 = axis_parameter(view_, mouse_start_, c0_, a), s = axis_parameter(view_, mouse_, c0_, a);
  if (s0 && s) grab_ = (*s - *s0) * a;
}

double ModalTransform::rotate_degrees() const {
  if (const auto v = typed_value()) return *v;
  double deg = sweep_ * kDeg;
  if (lock_ != AxisLock::None && axis_vector().dot(-view_.forward()) < 0.0) deg = -deg;
  return deg;
}

double ModalTransform::scale_factor() const {
  if (const auto v = typed_value()) return clamp_factor(*v);
  const auto c = view_.project(c0_);
  if (!c) return 1.0;
  const double d0 = std::max((mouse_start_ - c->head<2>()).norm(), 1.0);
  return clamp_factor((mouse_ - c->head<2>()).norm() / d0);
}

Manipulator ModalTransform::current() const {
  Manipulator m = start_;
  switch (kind_) {
    case TransformKind::Grab: {
      const auto v = typed_value();
      m.translation = start_.translation + (v ? Vec3(*v * axis_vector()) : grab_);
      break;
    }
    case TransformKind::Rotate: {
      const Vec3 axis = lock_ == AxisLock::None ? Vec3(-view_.forward()) : axis_vector();
      m.rotation = (Manipulator::axis_angle(axis, rotate_degrees()) * start_.rotation.normalized()).normalized();
      break;
    }
    case TransformKind::Scale: {
      const double f = scale_factor();
      const int i = axis_index(lock_);
      if (i < 0)
        m.scale = f * start_.scale;
      else
        m.scale[i] = f * start_.scale[i];
      break;
    }
  }
  return m;
}

std::string ModalTransform::status() const {
  static constexpr const char* kNames[] = {"Grab", "Rotate", "Scale"};
  std::string s = kNames[static_cast<int>(kind_)];
  s += "  ";
  const int i = axis_index(lock_);
  const auto typed = typed_value();
  if (i >= 0) {
    s += std::string(1, static_cast<char>('X' + i)) + (is_local(lock_) ? " (local)" : " (global)");
  } else if (kind_ == TransformKind::Grab) {
    s += typed ? "X (global)" : "free";
  } else {
    s += kind_ == TransformKind::Rotate ? "view" : "uniform";
  }
  s += ": ";
  const char* unit = kind_ == TransformKind::Rotate ? "\xC2\xB0" : "";
  if (typed) return s + typed_text_ + unit;
  std::string amount;
  if (kind_ == TransformKind::Grab && i < 0) {
    amount = "(" + format_number("%.4g", grab_.x()) + ", " + format_number("%.4g", grab_.y()) + ", " +
             format_number("%.4g", grab_.z()) + ")";
  } else if (kind_ == TransformKind::Grab) {
    amount = format_number("%.4g", grab_.dot(axis_vector()));
  } else if (kind_ == TransformKind::Rotate) {
    amount = format_number("%.1f", rotate_degrees()) + unit;
  } else {
    amount = format_number("%.4g", scale_factor());
  }
  // Typed text that is not a number yet ("-", "."): show it next to the mouse amount.
  if (!typed_text_.empty()) return s + typed_text_ + " (mouse " + amount + ")";
  return s + amount;
}

}  // namespace freeform::editor
