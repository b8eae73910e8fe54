#include "freeform/nonlinear/face_fans.h"

#include "freeform/common/error.h"
#include "freeform/operators/face_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace freeform {
namespace {

using Vec = Eigen::Vector3d;
Eigen::Map<const Vec> row(const double* p, int i) {
  return Eigen::Map<const Vec>(p + 3 * static_cast<std::ptrdiff_t>(i));
}

// Fit weight floor (cotangent units): no edge of a needle triangle drops out of the fit.
constexpr double kFitFloor = 1e-3;
// The one-sided membrane's bound (target_scale): a stretch counts up to this much.
constexpr double kMaxStretch = 1.5;
double fit_weight(double cot) { return std::max(cot, 0.0) + kFitFloor; }
// where_bent's ramp over bend_fraction. On a regular strip a pure twist measures about 0.3 (its
// edges along the strip turn about themselves, the diagonals half about themselves) and a pure
// bend about 0.7. With the share raised in proportion to the fraction the twisted survey bar
// was bistable (its twist spread or gathered in its middle as Anderson's history changed), from
// 0.4 it gathered at k = 3, from 0.5 it spreads in every run (docs/nonlinear.md, "What the
// gallery found", 48).
constexpr double kTwisted = 0.5, kBent = 0.8;
// A turn this small (sum of sin(angle / 2) over a face's edges) is no turn: rigid and rest fields.
constexpr double kNoTurn = 1e-12;

}  // namespace

FaceFans::FaceFans(const Mesh& mesh, const VertexData<int>& local, std::span<const Vertex> global, const double* rest,
                   const Laplacian& lap) {
  offset_.assign(1, 0);
  spoke_offset_.assign(1, 0);
  std::vector<std::array<double, 2>> cots;  // per face of the row's fan: |cot| at n and at j
  FaceData<int> index(static_cast<std::size_t>(mesh.n_faces()), -1);
  for (int i = 0; i < static_cast<int>(lap.rows()); ++i) {
    const std::size_t first = faces_.size();
    cots.clear();
    for (Halfedge h : mesh.outgoing(global[static_cast<std::size_t>(i)])) {
      if (!mesh.face(h).is_valid()) continue;
      const int j = local[mesh.to_vertex(h)], n = local[mesh.to_vertex(mesh.next(h))];
      if (j < 0 || n < 0) continue;
      // The operators' clamped cotangents (0 on a degenerate face); corner k weights the opposite edge.
      const detail::CornerWeights w = detail::corner_weights(row(rest, i), row(rest, j), row(rest, n));
      int& face = index[mesh.face(h)];
      if (face < 0) {
        face = static_cast<int>(corners_.size());
        corners_.push_back({i, j, n});
      }
      const std::array<int, 3>& c = corners_[static_cast<std::size_t>(face)];
      const int corner = c[0] == i ? 0 : c[1] == i ? 1 : 2;
      // An oriented manifold's halfedges give every row its corners in the face's own cycle.
      if (c[static_cast<std::size_t>((corner + 1) % 3)] != j || c[static_cast<std::size_t>((corner + 2) % 3)] != n)
        throw InternalError("FaceFans: a face's corners are not in the order of its halfedges");
      faces_.push_back({j, n, face, corner, 0.0, 0.0});
      // The fit's three edges (i, j), (i, n), (j, n), gathered on the row's ring.
      add_spoke(i, j, i, fit_weight(w.cot[2]), rest);
      add_spoke(i, n, i, fit_weight(w.cot[1]), rest);
      add_spoke(i, j, n, fit_weight(w.cot[0]), rest);
      add_spoke(i, n, j, fit_weight(w.cot[0]), rest);
      cots.push_back({std::abs(w.cot[2]), std::abs(w.cot[1])});
    }
    // Each edge's weight in lap, split between the faces of the fan that hold it.
    const std::span<Face> fan(faces_.data() + first, faces_.size() - first);
    for (Laplacian::InnerIterator e(lap, i); e; ++e) {
      const int j = static_cast<int>(e.col());
      if (j == i) continue;
      double sum = 0.0;
      int count = 0;
      for (std::size_t k = 0; k < fan.size(); ++k) {
        if (fan[k].j == j) sum += cots[k][0], ++count;
        if (fan[k].n == j) sum += cots[k][1], ++count;
      }
      const bool even = !(sum > 1e-12);
      for (std::size_t k = 0; k < fan.size(); ++k) {
        if (fan[k].j == j) fan[k].wj = e.value() * (even ? 1.0 / count : cots[k][0] / sum);
        if (fan[k].n == j) fan[k].wn = e.value() * (even ? 1.0 / count : cots[k][1] / sum);
      }
    }
    offset_.push_back(static_cast<int>(faces_.size()));
    spoke_offset_.push_back(static_cast<int>(spokes_.size()));
  }
}

void FaceFans::add_spoke(int i, int a, int b, double w, const double* rest) {
  const auto first = spokes_.begin() + spoke_offset_[static_cast<std::size_t>(i)];
  auto it = std::find_if(first, spokes_.end(), [a](const Spoke& s) { return s.a == a; });
  if (it == spokes_.end()) it = spokes_.insert(it, {a, Vec::Zero()});
  it->g += w * (row(rest, a) - row(rest, b));
}

Eigen::Matrix3d FaceFans::covariance(int i, const double* x) const {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  const Vec xi = row(x, i);
  for (int k = spoke_offset_[static_cast<std::size_t>(i)]; k < spoke_offset_[static_cast<std::size_t>(i) + 1]; ++k) {
    const Spoke& e = spokes_[static_cast<std::size_t>(k)];
    s.noalias() += (row(x, e.a) - xi) * e.g.transpose();
  }
  return s;
}

double FaceFans::target_scale(double stretch, const OneSided& one_sided) {
  // An edge turned against its target (a cold start's first step under a large rotation)
  // counts as fully compressed, not more.
  stretch = std::clamp(stretch, 0.0, kMaxStretch);
  if (one_sided.grown > 1.0 && stretch < 1.0) {
    // An edge between its rest length and its grown target is taken as it is; a shorter one is
    // pushed out from its rest length, as an ungrown edge is.
    const double from_rest = stretch * one_sided.grown;
    if (from_rest >= 1.0) return stretch;
    OneSided ungrown = one_sided;
    ungrown.grown = 1.0;
    return target_scale(from_rest, ungrown) / one_sided.grown;
  }
  if (stretch < 1.0) {
    const double u = 1.0 - stretch, w = one_sided.onset;
    return 1.0 + one_sided.compression_gain * (u >= w ? u - 0.5 * w : 0.5 * u * u / w);
  }
  return 1.0 + one_sided.stretch_share * (stretch - 1.0);
}

double FaceFans::bend_fraction(int face, const std::vector<Eigen::Quaterniond>& q, const double* rest) const {
  const std::array<int, 3>& c = corners_[static_cast<std::size_t>(face)];
  double bend = 0.0, twist = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const int a = c[k], b = c[(k + 1) % 3];
    // The turn from a's rotation to b's as a vector along its axis, sin(angle / 2) long.
    const Eigen::Quaterniond d = q[static_cast<std::size_t>(a)].conjugate() * q[static_cast<std::size_t>(b)];
    const Vec w = (d.w() < 0.0 ? -1.0 : 1.0) * d.vec();
    Vec r = row(rest, b) - row(rest, a);
    const double length = r.norm();
    if (!(length > 0.0)) continue;
    r /= length;
    twist += std::abs(w.dot(r));
    bend += w.cross(r).norm();
  }
  return bend + twist > kNoTurn ? bend / (bend + twist) : 0.0;
}

OneSided FaceFans::where_bent(const OneSided& one_sided, double bend_fraction) {
  OneSided out = one_sided;
  if (out.bent_stretch_share <= out.stretch_share) return out;
  const double t = std::clamp((bend_fraction - kTwisted) / (kBent - kTwisted), 0.0, 1.0);
  out.stretch_share += t * (out.bent_stretch_share - out.stretch_share);
  return out;
}

Eigen::Matrix3d FaceFans::mean(int face, const std::vector<Eigen::Matrix3d>& rot) const {
  const std::array<int, 3>& c = corners_[static_cast<std::size_t>(face)];
  return (rot[static_cast<std::size_t>(c[0])] + rot[static_cast<std::size_t>(c[1])] +
          rot[static_cast<std::size_t>(c[2])]) /
         3.0;
}

FaceFans::EdgeTerms FaceFans::edge_terms(int face, const Eigen::Matrix3d& mean, const double* rest, const double* x,
                                         const OneSided& one_sided) const {
  const std::array<int, 3>& c = corners_[static_cast<std::size_t>(face)];
  // The target t = (mean + I) r, scaled by the edge's stretch along it, minus the rest edge r.
  const auto term = [&](int a, int b) -> Vec {
    const Vec r = row(rest, b) - row(rest, a);
    const Vec t = mean * r + r;
    const double tt = t.squaredNorm();
    const double stretch = tt > 0.0 ? (row(x, b) - row(x, a)).dot(t) / tt : 1.0;
    return target_scale(stretch, one_sided) * t - r;
  };
  return {term(c[0], c[1]), term(c[0], c[2]), term(c[1], c[2])};
}

Eigen::Vector3d FaceFans::rotated(int i, const std::vector<EdgeTerms>& terms) const {
  Vec b = Vec::Zero();
  for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k) {
    const Face& f = faces_[static_cast<std::size_t>(k)];
    const EdgeTerms& t = terms[static_cast<std::size_t>(f.face)];
    // Row i at corner 0 has edges 01 and 02; at 1, 12 and 10; at 2, 20 and 21.
    const Vec tj = f.corner == 0 ? t[0] : f.corner == 1 ? t[2] : Vec(-t[1]);
    const Vec tn = f.corner == 0 ? t[1] : f.corner == 1 ? Vec(-t[0]) : Vec(-t[2]);
    b += f.wj * tj + f.wn * tn;
  }
  return b;
}

Eigen::Vector3d FaceFans::rotated(int i, const double* rest, const std::vector<Eigen::Matrix3d>& means) const {
  Vec b = Vec::Zero();
  const Vec ri = row(rest, i);
  for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k) {
    const Face& f = faces_[static_cast<std::size_t>(k)];
    const Vec ej = row(rest, f.j) - ri, en = row(rest, f.n) - ri;
    b += means[static_cast<std::size_t>(f.face)] * (f.wj * ej + f.wn * en);
  }
  return b;
}

}  // namespace freeform
