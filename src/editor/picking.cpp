#include "editor/picking.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace freeform::editor {
namespace {

constexpr double kRelTol = 1e-6;  // see the visibility definition in picking.h
constexpr double kAbsTol = 1e-7;  // times the bounding-box diagonal

// Even-odd rule (crossing count of a ray towards +x).
bool inside_polygon(const Eigen::Vector2d& p, std::span<const Eigen::Vector2d> poly) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

}  // namespace

ScreenPicker::ScreenPicker(const Mesh& mesh, const VertexData<Vec3>& positions, const Bvh& bvh, const ScreenView& view)
    : mesh_(mesh), positions_(positions), bvh_(bvh), view_(view) {
  const int n = mesh.n_vertices();
  if (static_cast<int>(positions.size()) != n)
    throw InvalidInput("picking: got " + std::to_string(positions.size()) + " positions for a mesh with " +
                       std::to_string(n) + " vertices");
  if (bvh.n_faces() != mesh.n_faces())
    throw InvalidInput("picking: the BVH has " + std::to_string(bvh.n_faces()) + " faces, the mesh " +
                       std::to_string(mesh.n_faces()) + " (rebuild the BVH for this mesh)");
  if (view.width <= 0 || view.height <= 0) throw InvalidInput("picking: the viewport size must be > 0");
  abs_tol_ = kAbsTol * (bvh.bounds_max() - bvh.bounds_min()).norm();
  // The mapping of ScreenView::project with the matrix formed once.
  const Eigen::Matrix4d vp = view.view_projection();
  px_.resize(static_cast<std::size_t>(n));
  front_.assign(static_cast<std::size_t>(n), 0);
  vis_.assign(static_cast<std::size_t>(n), 0);
  for (Vertex v : mesh.vertices()) {
    const Eigen::Vector4d c = vp * positions[v].homogeneous();
    if (!(c.w() > 0.0) || mesh.is_isolated(v)) continue;
    front_[v.idx()] = 1;
    px_[v.idx()] = Eigen::Vector2d(0.5 * (c.x() / c.w() + 1.0) * view.width, 0.5 * (1.0 - c.y() / c.w()) * view.height);
  }
}

bool ScreenPicker::on_screen(int i) const {
  const Eigen::Vector2d& p = px_[i];
  return front_[i] && p.x() >= 0.0 && p.x() <= view_.width && p.y() >= 0.0 && p.y() <= view_.height;
}

bool ScreenPicker::cast(int i) const {
  const Vec3 to = positions_.raw()[i] - view_.camera.eye;
  const double dist = to.norm();
  if (!(dist > 0.0)) return false;  // the eye sits on the vertex
  const double limit = (1.0 - kRelTol) * dist - abs_tol_;
  if (limit <= 0.0) return true;
  return !bvh_.occluded(Ray{view_.camera.eye, to / dist}, limit, Vertex(i));
}

bool ScreenPicker::visible(Vertex v) const {
  if (!v.is_valid() || v.idx() >= mesh_.n_vertices())
    throw InvalidInput("picking: vertex " + std::to_string(v.idx()) + " is not in the mesh");
  const int i = v.idx();
  if (!on_screen(i)) return false;
  if (vis_[i] == 0) vis_[i] = cast(i) ? 1 : 2;
  return vis_[i] == 1;
}

std::vector<Vertex> ScreenPicker::keep_visible(const std::vector<int>& candidates) const {
  std::vector<Vertex> out;
  out.reserve(candidates.size());
  for (int i : candidates) {
    if (vis_[i] == 0) vis_[i] = cast(i) ? 1 : 2;
    if (vis_[i] == 1) out.emplace_back(i);
  }
  return out;
}

std::optional<Eigen::Vector2d> ScreenPicker::pixel(Vertex v) const {
  if (!v.is_valid() || v.idx() >= mesh_.n_vertices() || !front_[v.idx()]) return std::nullopt;
  return px_[v.idx()];
}

std::vector<Vertex> ScreenPicker::brush(const Eigen::Vector2d& center_px, double radius_px) const {
  if (!center_px.allFinite() || !std::isfinite(radius_px) || radius_px < 0.0)
    throw InvalidInput("brush: the centre must be finite and the radius a finite number >= 0");
  const double r2 = radius_px * radius_px;
  std::vector<int> candidates;
  for (int i = 0; i < mesh_.n_vertices(); ++i)
    if (on_screen(i) && (px_[i] - center_px).squaredNorm() <= r2) candidates.push_back(i);
  return keep_visible(candidates);
}

std::vector<Vertex> ScreenPicker::lasso(std::span<const Eigen::Vector2d> polygon_px) const {
  if (polygon_px.size() < 3) return {};
  Eigen::Vector2d lo = polygon_px[0], hi = polygon_px[0];
  for (const Eigen::Vector2d& p : polygon_px) {
    if (!p.allFinite()) throw InvalidInput("lasso: every polygon point must be finite");
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  std::vector<int> candidates;
  for (int i = 0; i < mesh_.n_vertices(); ++i) {
    if (!on_screen(i)) continue;
    const Eigen::Vector2d& p = px_[i];
    if (p.x() < lo.x() || p.y() < lo.y() || p.x() > hi.x() || p.y() > hi.y()) continue;
    if (inside_polygon(p, polygon_px)) candidates.push_back(i);
  }
  return keep_visible(candidates);
}

std::optional<SurfacePick> ScreenPicker::pick(const Eigen::Vector2d& px) const {
  if (!px.allFinite() || px.x() < 0.0 || px.y() < 0.0 || px.x() > view_.width || px.y() > view_.height)
    return std::nullopt;
  const Ray ray = view_.ray(px);
  const std::optional<RayHit> hit = bvh_.intersect(ray);
  if (!hit) return std::nullopt;
  SurfacePick out;
  out.face = hit->face;
  out.point = ray.origin + hit->t * ray.direction;
  out.barycentric = hit->barycentric;
  out.distance = hit->t;
  double best = std::numeric_limits<double>::infinity();
  for (Vertex v : mesh_.vertices(hit->face)) {
    const double d = (positions_[v] - out.point).squaredNorm();
    if (d < best) {
      best = d;
      out.vertex = v;
    }
  }
  return out;
}

}  // namespace freeform::editor
