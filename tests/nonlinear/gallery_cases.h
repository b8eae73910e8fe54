// The gallery's edits (bench/bench_gallery.cpp, test_gallery_subset.cpp): seeded limb edits on
// real meshes that nobody tuned the nonlinear model for. A limb edit takes a geodesic ball
// around an extremity (farthest-point samples of the edge-path distance) as the support and its
// inner third as the handle; the limb's axis runs from the ball's rim to the handle, and the
// handle is bent away from the body about the rim, twisted about the axis, or pulled along it;
// drag_cases() moves it sideways instead, its orientation kept, as a translate gizmo does;
// scale_cases() scales it about its centre, as a scale gizmo does; turn_cases() turns it about its
// centre, as a rotate gizmo does; bump_cases() pulls a disc of the surface away from the body or
// pushes it in, the classic freeform edit.
#pragma once

#include "survey_shapes.h"

#include "freeform/regions/selectors.h"

#include <algorithm>
#include <random>
#include <string>
#include <vector>

namespace freeform::test {

enum class LimbEdit { Bend, Twist, Pull, Drag, Scale, Turn };

// The length of the mesh's bounding-box diagonal.
inline double diagonal(const Mesh& mesh) {
  Vec3 lo = mesh.position(Vertex(0)), hi = lo;
  for (Vertex v : mesh.vertices()) lo = lo.cwiseMin(mesh.position(v)), hi = hi.cwiseMax(mesh.position(v));
  return (hi - lo).norm();
}

inline Vec3 centroid(const Mesh& mesh) {
  Vec3 c = Vec3::Zero();
  for (Vertex v : mesh.vertices()) c += mesh.position(v) / static_cast<double>(mesh.n_vertices());
  return c;
}

// Farthest-point samples of the edge-path distance, starting at the vertex farthest from the
// centroid: the tips of limbs, tails and heads first.
inline std::vector<Vertex> extremities(const Mesh& mesh, int count) {
  const Vec3 c = centroid(mesh);
  Vertex first(0);
  for (Vertex v : mesh.vertices())
    if ((mesh.position(v) - c).norm() > (mesh.position(first) - c).norm()) first = v;
  std::vector<Vertex> out{first};
  VertexData<double> nearest = geodesic_distance(mesh, first);
  while (static_cast<int>(out.size()) < count) {
    Vertex next(0);
    for (Vertex v : mesh.vertices())
      if (std::isfinite(nearest[v]) && nearest[v] > nearest[next]) next = v;
    out.push_back(next);
    const VertexData<double> d = geodesic_distance(mesh, next);
    for (Vertex v : mesh.vertices()) nearest[v] = std::min(nearest[v], d[v]);
  }
  return out;
}

struct Limb {
  std::vector<Vertex> support, handle;
  Vec3 rim = Vec3::Zero();    // centroid of the support's boundary ring (the limb's root)
  Vec3 tip = Vec3::Zero();    // the handle's centroid
  Vec3 axis = Vec3::UnitZ();  // from rim to tip, unit
};

// The geodesic ball of `radius` around `tip_vertex` and its inner third; nullopt when the
// ball is not a limb (it reaches most of the mesh, or its rim is empty).
inline std::optional<Limb> limb(const Mesh& mesh, Vertex tip_vertex, double radius) {
  Limb l;
  const Vec3 c = mesh.position(tip_vertex);
  l.support = select_geodesic(mesh, c, radius, "support");
  l.handle = select_geodesic(mesh, c, radius / 3.0, "handle");
  // A support that is all handle (a small part whole, e.g. a loose piece of a real file) is no limb.
  if (l.support.size() * 2 > static_cast<std::size_t>(mesh.n_vertices()) || l.handle.size() < 3 ||
      l.handle.size() >= l.support.size())
    return std::nullopt;
  std::vector<char> in(static_cast<std::size_t>(mesh.n_vertices()), 0);
  for (Vertex v : l.support) in[static_cast<std::size_t>(v.idx())] = 1;
  int rim_count = 0;
  for (Vertex v : l.support) {
    bool on_rim = false;
    for (Halfedge h : mesh.outgoing(v)) on_rim = on_rim || !in[static_cast<std::size_t>(mesh.to_vertex(h).idx())];
    if (on_rim) l.rim += mesh.position(v), ++rim_count;
  }
  if (rim_count == 0) return std::nullopt;
  l.rim /= rim_count;
  for (Vertex v : l.handle) l.tip += mesh.position(v) / static_cast<double>(l.handle.size());
  if (!((l.tip - l.rim).norm() > 0)) return std::nullopt;
  l.axis = (l.tip - l.rim).normalized();
  return l;
}

// Across the limb's axis, away from the body's centroid (unit).
inline Vec3 away_from_body(const Mesh& mesh, const Limb& l) {
  Vec3 away = l.rim - centroid(mesh);
  away -= away.dot(l.axis) * l.axis;
  if (away.norm() < 1e-9 * (l.tip - l.rim).norm()) away = l.axis.unitOrthogonal();
  return away.normalized();
}

// Bend about the rim (the handle swings away from the body's centroid), twist about the axis,
// pull along it, drag the handle sideways (away from the body, not turned), scale it about its
// centre or turn it there (about the bend's axis, so that its end swings away from the body) by
// `amount` (degrees; for a pull or a drag the fraction of the limb's length; for a scale the
// factor).
inline Eigen::Affine3d limb_transform(const Mesh& mesh, const Limb& l, LimbEdit kind, double amount) {
  if (kind == LimbEdit::Scale)
    return Eigen::Translation3d(l.tip) * Eigen::Scaling(amount) * Eigen::Translation3d(-l.tip);
  if (kind == LimbEdit::Pull) return Eigen::Affine3d(Eigen::Translation3d(amount * (l.tip - l.rim)));
  if (kind == LimbEdit::Twist) return rotation_about(l.rim, amount, l.axis);
  const Vec3 away = away_from_body(mesh, l);
  if (kind == LimbEdit::Turn) return rotation_about(l.tip, amount, l.axis.cross(away));
  if (kind == LimbEdit::Drag) return Eigen::Affine3d(Eigen::Translation3d(amount * (l.tip - l.rim).norm() * away));
  // Rotating about axis x away moves the tip (along the axis from the rim) toward `away`.
  return rotation_about(l.rim, amount, l.axis.cross(away));
}

inline Shape limb_case(const std::string& name, const Mesh& mesh, const std::vector<const Limb*>& limbs,
                       const std::vector<Eigen::Affine3d>& transforms) {
  Shape s{name, mesh, {}};
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    s.edit.support.insert(s.edit.support.end(), limbs[i]->support.begin(), limbs[i]->support.end());
    EditHandle h;
    h.vertices = limbs[i]->handle;
    h.matrix = transforms[i];
    s.edit.handles.push_back(h);
  }
  std::sort(s.edit.support.begin(), s.edit.support.end());
  s.edit.support.erase(std::unique(s.edit.support.begin(), s.edit.support.end()), s.edit.support.end());
  return s;
}

// Seeded edits on each of `n_limbs` limbs (support radius `radius_frac` of the diagonal): a bend
// (60-150 degrees), a twist (90-180), on the first a pull (30 %), and both first limbs bent at
// once (two handles) when their supports are disjoint.
// The limbs at the first `n_limbs` extremities (support radius `radius_frac` of the diagonal).
inline std::vector<Limb> limbs_of(const Mesh& mesh, int n_limbs, double radius_frac) {
  const double radius = radius_frac * diagonal(mesh);
  std::vector<Limb> limbs;
  for (Vertex tip : extremities(mesh, n_limbs))
    if (auto l = limb(mesh, tip, radius)) limbs.push_back(std::move(*l));
  return limbs;
}

inline std::vector<Shape> limb_cases(const std::string& mesh_name, const Mesh& mesh, int n_limbs, double radius_frac,
                                     std::mt19937& rng) {
  const std::vector<Limb> limbs = limbs_of(mesh, n_limbs, radius_frac);
  std::uniform_real_distribution<double> bend(60, 150), twist(90, 180);
  std::vector<Shape> out;
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    const std::string stem = mesh_name + "-limb" + std::to_string(i);
    const double b = std::round(bend(rng)), t = std::round(twist(rng));
    out.push_back(limb_case(stem + "-bend" + std::to_string(static_cast<int>(b)), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Bend, b)}));
    out.push_back(limb_case(stem + "-twist" + std::to_string(static_cast<int>(t)), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Twist, t)}));
    if (i == 0)
      out.push_back(
          limb_case(stem + "-pull30", mesh, {&limbs[i]}, {limb_transform(mesh, limbs[i], LimbEdit::Pull, 0.3)}));
  }
  if (limbs.size() >= 2) {
    // Disjoint supports only: two handles inside one connected support would be another edit.
    std::vector<Vertex> both;
    std::set_intersection(limbs[0].support.begin(), limbs[0].support.end(), limbs[1].support.begin(),
                          limbs[1].support.end(), std::back_inserter(both));
    if (both.empty()) {
      const double b = std::round(bend(rng));
      out.push_back(limb_case(
          mesh_name + "-two-limbs-bend" + std::to_string(static_cast<int>(b)), mesh, {&limbs[0], &limbs[1]},
          {limb_transform(mesh, limbs[0], LimbEdit::Bend, b), limb_transform(mesh, limbs[1], LimbEdit::Bend, b)}));
    }
  }
  return out;
}

// A family of edits on a mesh: (mesh name, mesh, limbs or discs, their radius as a fraction of the
// diagonal, random numbers) to cases.
using CaseMaker = std::vector<Shape> (*)(const std::string&, const Mesh&, int, double, std::mt19937&);

// The same limbs moved without turning the handle, as a translate gizmo does: each dragged
// sideways (away from the body) by 40-100 % of its length, the first also pushed toward the
// body along its axis by 20-40 % (a compression). The support must find its own rotations: the
// guidance field is the identity.
inline std::vector<Shape> drag_cases(const std::string& mesh_name, const Mesh& mesh, int n_limbs, double radius_frac,
                                     std::mt19937& rng) {
  const std::vector<Limb> limbs = limbs_of(mesh, n_limbs, radius_frac);
  std::uniform_int_distribution<int> sideways(40, 100), push(20, 40);
  std::vector<Shape> out;
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    const std::string stem = mesh_name + "-limb" + std::to_string(i);
    const int d = sideways(rng);
    out.push_back(limb_case(stem + "-drag" + std::to_string(d), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Drag, d / 100.0)}));
    if (i > 0) continue;
    const int c = push(rng);
    out.push_back(limb_case(stem + "-push" + std::to_string(c), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Pull, -c / 100.0)}));
  }
  return out;
}

// The same limbs' handles scaled about their centres, as a scale gizmo does: each grown by 1.3-2,
// the first also shrunk to 0.5-0.75. The support tapers between the scaled handle and the rim.
inline std::vector<Shape> scale_cases(const std::string& mesh_name, const Mesh& mesh, int n_limbs, double radius_frac,
                                      std::mt19937& rng) {
  const std::vector<Limb> limbs = limbs_of(mesh, n_limbs, radius_frac);
  std::uniform_int_distribution<int> grow(130, 200), shrink(50, 75);
  std::vector<Shape> out;
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    const std::string stem = mesh_name + "-limb" + std::to_string(i);
    const int g = grow(rng);
    out.push_back(limb_case(stem + "-grow" + std::to_string(g), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Scale, g / 100.0)}));
    if (i > 0) continue;
    const int s = shrink(rng);
    out.push_back(limb_case(stem + "-shrink" + std::to_string(s), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Scale, s / 100.0)}));
  }
  return out;
}

// The same limbs' handles turned in place about their centres, as a rotate gizmo turns them:
// each by 45-120 degrees about the bend's axis (the end swings away from the body), so the limb
// must bend one way at its root and back below the handle (a twist about the limb's axis is the
// same through the centre as through the rim: limb_cases has it).
inline std::vector<Shape> turn_cases(const std::string& mesh_name, const Mesh& mesh, int n_limbs, double radius_frac,
                                     std::mt19937& rng) {
  const std::vector<Limb> limbs = limbs_of(mesh, n_limbs, radius_frac);
  std::uniform_int_distribution<int> tilt(45, 120);
  std::vector<Shape> out;
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    const std::string stem = mesh_name + "-limb" + std::to_string(i);
    const int a = tilt(rng);
    out.push_back(limb_case(stem + "-turn" + std::to_string(a), mesh, {&limbs[i]},
                            {limb_transform(mesh, limbs[i], LimbEdit::Turn, a)}));
  }
  return out;
}

// The faces whose corners are all in `region` (sorted): the sum of their normals times twice their
// areas, and twice their total area.
inline std::pair<Vec3, double> region_normal(const Mesh& mesh, const std::vector<Vertex>& region) {
  Vec3 n = Vec3::Zero();
  double area = 0;
  auto in = [&](Vertex v) { return std::binary_search(region.begin(), region.end(), v); };
  for (Face f : mesh.faces()) {
    const auto [a, b, c] = mesh.vertices(f);
    if (!in(a) || !in(b) || !in(c)) continue;
    const Vec3 twice = (mesh.position(b) - mesh.position(a)).cross(mesh.position(c) - mesh.position(a));
    n += twice, area += twice.norm();
  }
  return {n, area};
}

// Discs of the surface (around seeded vertices: geodesic balls of half `radius_frac` of the
// diagonal, a limb's radius halved, their inner third the handle), the handle moved along the
// disc's normal without turning: `n_bumps` pulled out by 50-120 % of the disc's radius, and a
// dent pushed in by 20-40 %. A ball that is not a nearly flat disc (its mean normal under half its
// area: it wraps round a thin part) or reaches half the mesh is skipped.
inline std::vector<Shape> bump_cases(const std::string& mesh_name, const Mesh& mesh, int n_bumps, double radius_frac,
                                     std::mt19937& rng) {
  const double radius = 0.5 * radius_frac * diagonal(mesh);
  std::uniform_int_distribution<int> vertex(0, mesh.n_vertices() - 1), out_by(50, 120), in_by(20, 40);
  std::vector<Shape> out;
  for (int tries = 0, made = 0; tries < 20 * (n_bumps + 1) && made < n_bumps + 1; ++tries) {
    const Vec3 c = mesh.position(Vertex(vertex(rng)));
    const int amount = made < n_bumps ? out_by(rng) : -in_by(rng);
    Limb l;
    l.support = select_geodesic(mesh, c, radius, "support");
    l.handle = select_geodesic(mesh, c, radius / 3.0, "handle");
    // On a coarse mesh the disc can be all handle: no free vertex to bend (the edit is refused).
    if (l.support.size() * 2 > static_cast<std::size_t>(mesh.n_vertices()) || l.handle.size() < 3 ||
        l.handle.size() >= l.support.size())
      continue;
    const auto [n, area] = region_normal(mesh, l.support);
    if (n.norm() < 0.5 * area) continue;
    // A handle of a few vertices may hold no whole face: the disc's normal then.
    const Vec3 handle_normal = region_normal(mesh, l.handle).first;
    const Vec3 move = amount / 100.0 * radius * (handle_normal.norm() > 0 ? handle_normal : n).normalized();
    const std::string name =
        mesh_name + (amount > 0 ? "-bump" : "-dent") + std::to_string(made) + "-" + std::to_string(std::abs(amount));
    out.push_back(limb_case(name, mesh, {&l}, {Eigen::Affine3d(Eigen::Translation3d(move))}));
    ++made;
  }
  return out;
}

}  // namespace freeform::test
