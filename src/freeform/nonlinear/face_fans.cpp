#include "freeform/nonlinear/face_fans.h"

#include <algorithm>
#include <cmath>

namespace freeform {
namespace {

using Vec = Eigen::Vector3d;
Eigen::Map<const Vec> row(const double* p, int i) {
  return Eigen::Map<const Vec>(p + 3 * static_cast<std::ptrdiff_t>(i));
}

// Fit weight floor (cotangent units): no edge of a needle triangle drops out of the fit.
constexpr double kFitFloor = 1e-3;
constexpr double kCotClamp = 1e5;  // as the operators' cotangents (operators/face_geometry.h)

// Cotangent of the corner at a of triangle (a, b, c).
double cot(const double* rest, int a, int b, int c) {
  const Vec u = row(rest, b) - row(rest, a), v = row(rest, c) - row(rest, a);
  return std::clamp(u.dot(v) / std::max(u.cross(v).norm(), 1e-300), -kCotClamp, kCotClamp);
}

double fit_weight(double c) { return std::max(c, 0.0) + kFitFloor; }

}  // namespace

FaceFans::FaceFans(const Mesh& mesh, const VertexData<int>& local, std::span<const Vertex> global, const double* rest,
                   const Laplacian& lap) {
  offset_.assign(1, 0);
  for (int i = 0; i < static_cast<int>(lap.rows()); ++i) {
    const std::size_t first = faces_.size();
    for (Halfedge h : mesh.outgoing(global[static_cast<std::size_t>(i)])) {
      if (!mesh.face(h).is_valid()) continue;
      const int j = local[mesh.to_vertex(h)], n = local[mesh.to_vertex(mesh.next(h))];
      if (j >= 0 && n >= 0)
        faces_.push_back({j, n, 0.0, 0.0, fit_weight(cot(rest, n, i, j)), fit_weight(cot(rest, j, i, n)),
                          fit_weight(cot(rest, i, j, n))});
    }
    // Each edge's weight in lap, split between the faces of the fan that hold it.
    const std::span<Face> fan(faces_.data() + first, faces_.size() - first);
    for (Laplacian::InnerIterator e(lap, i); e; ++e) {
      const int j = static_cast<int>(e.col());
      if (j == i) continue;
      double sum = 0.0;
      int count = 0;
      for (const Face& f : fan) {
        if (f.j == j) sum += std::abs(cot(rest, f.n, i, j)), ++count;
        if (f.n == j) sum += std::abs(cot(rest, f.j, i, f.n)), ++count;
      }
      for (Face& f : fan) {
        const bool even = !(sum > 1e-12);
        if (f.j == j) f.wj = e.value() * (even ? 1.0 / count : std::abs(cot(rest, f.n, i, j)) / sum);
        if (f.n == j) f.wn = e.value() * (even ? 1.0 / count : std::abs(cot(rest, f.j, i, f.n)) / sum);
      }
    }
    offset_.push_back(static_cast<int>(faces_.size()));
  }
}

Eigen::Matrix3d FaceFans::covariance(int i, const double* x, const double* rest) const {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  const Vec xi = row(x, i), ri = row(rest, i);
  for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k) {
    const Face& f = faces_[static_cast<std::size_t>(k)];
    s += f.cj * (row(x, f.j) - xi) * (row(rest, f.j) - ri).transpose();
    s += f.cn * (row(x, f.n) - xi) * (row(rest, f.n) - ri).transpose();
    s += f.ci * (row(x, f.n) - row(x, f.j)) * (row(rest, f.n) - row(rest, f.j)).transpose();
  }
  return s;
}

Eigen::Vector3d FaceFans::rotated(int i, const double* rest, const std::vector<Eigen::Matrix3d>& rot) const {
  Vec b = Vec::Zero();
  const Vec ri = row(rest, i);
  const Eigen::Matrix3d& rot_i = rot[static_cast<std::size_t>(i)];
  for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k) {
    const Face& f = faces_[static_cast<std::size_t>(k)];
    const Eigen::Matrix3d mean =
        (rot_i + rot[static_cast<std::size_t>(f.j)] + rot[static_cast<std::size_t>(f.n)]) / 3.0;
    b += mean * (f.wj * (row(rest, f.j) - ri) + f.wn * (row(rest, f.n) - ri));
  }
  return b;
}

}  // namespace freeform
