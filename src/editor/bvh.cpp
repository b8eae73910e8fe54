#include "editor/bvh.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace freeform::editor {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Nodes with at most this many triangles become leaves.
constexpr int kLeafSize = 2;
// Depth <= 63 bit splits + 31 median splits of equal codes, and the stack holds <= depth + 1.
constexpr int kStackSize = 128;
// Box exits are scaled by this to stay conservative under rounding (PBRT's 1 + 2 gamma(3)).
constexpr double kEpsM = std::numeric_limits<double>::epsilon() * 0.5;
constexpr double kExitScale = 1.0 + 2.0 * (3.0 * kEpsM) / (1.0 - 3.0 * kEpsM);
// Barycentric slack so a ray through a shared edge cannot slip between its two triangles.
constexpr double kBaryTol = 1e-12;
// |det| / (|e1| |e2| |d|) below this: the ray runs along the triangle's plane (or the triangle
// is degenerate) and the hit is too ill-conditioned to report.
constexpr double kDetRel = 1e-12;

struct Box {
  double lo[3] = {kInf, kInf, kInf};
  double hi[3] = {-kInf, -kInf, -kInf};
  void grow(const double* p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
};

// 21 bits of each coordinate interleaved (x in the lowest of each triple).
std::uint64_t spread21(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// LSD radix sort of (key, value) pairs by key, 11 bits per pass (63-bit keys: 6 passes).
void radix_sort(std::vector<std::pair<std::uint64_t, int>>& items) {
  std::vector<std::pair<std::uint64_t, int>> tmp(items.size());
  for (int shift = 0; shift < 63; shift += 11) {
    std::vector<std::size_t> count(2049, 0);
    for (const auto& it : items) ++count[((it.first >> shift) & 2047) + 1];
    for (int b = 0; b < 2048; ++b) count[b + 1] += count[b];
    for (const auto& it : items) tmp[count[(it.first >> shift) & 2047]++] = it;
    items.swap(tmp);
  }
}

// Möller–Trumbore: true with t in (0, t_max) on a hit; u, v are the weights of p1 and p2.
inline bool hit_triangle(const Vec3& o, const Vec3& d, const Vec3& p0, const Vec3& p1, const Vec3& p2, double t_max,
                         double& t, double& u, double& v) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const Vec3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  const double scale = e1.squaredNorm() * e2.squaredNorm() * d.squaredNorm();
  if (!(det * det > kDetRel * kDetRel * scale)) return false;
  const double inv_det = 1.0 / det;
  const Vec3 s = o - p0;
  u = s.dot(pv) * inv_det;
  if (u < -kBaryTol || u > 1.0 + kBaryTol) return false;
  const Vec3 q = s.cross(e1);
  v = d.dot(q) * inv_det;
  if (v < -kBaryTol || u + v > 1.0 + kBaryTol) return false;
  t = e2.dot(q) * inv_det;
  return t > 0.0 && t < t_max;
}

}  // namespace

// Linear BVH: triangles sorted along a Morton curve of their centroids, each node split where
// the highest differing code bit changes (the spatial median of the node's Morton cell; equal
// codes split at the middle). O(F) for the codes and the radix sort, then boxes bottom-up.
Bvh::Bvh(const Mesh& mesh, const VertexData<Vec3>& positions) {
  if (static_cast<int>(positions.size()) != mesh.n_vertices())
    throw InvalidInput("BVH: got " + std::to_string(positions.size()) + " positions for a mesh with " +
                       std::to_string(mesh.n_vertices()) + " vertices");
  set_positions(positions);
  const int n = mesh.n_faces();
  if (n == 0) return;

  tris_.resize(static_cast<std::size_t>(n));
  std::vector<Vec3> centroid(static_cast<std::size_t>(n));
  Box cbox;
  for (Face f : mesh.faces()) {
    const auto vs = mesh.vertices(f);
    tris_[f.idx()] = {vs[0].idx(), vs[1].idx(), vs[2].idx()};
    centroid[f.idx()] = (pos_[vs[0].idx()] + pos_[vs[1].idx()] + pos_[vs[2].idx()]) / 3.0;
    cbox.grow(centroid[f.idx()].data());
  }
  std::vector<std::pair<std::uint64_t, int>> items(static_cast<std::size_t>(n));
  // One scale for all axes (a cube), so a thin dimension is not split as often as a long one.
  const double extent = std::max({cbox.hi[0] - cbox.lo[0], cbox.hi[1] - cbox.lo[1], cbox.hi[2] - cbox.lo[2]});
  const double scale = extent > 0.0 && std::isfinite(extent) ? 2097151.0 / extent : 0.0;
  for (int i = 0; i < n; ++i) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double q = (centroid[i][a] - cbox.lo[a]) * scale;  // NaN (overflowing input) -> 0
      code |= spread21(static_cast<std::uint64_t>(q > 0.0 ? std::min(q, 2097151.0) : 0.0)) << a;
    }
    items[i] = {code, i};
  }
  radix_sort(items);

  std::vector<std::array<int, 3>> unsorted;
  unsorted.swap(tris_);
  tris_.resize(static_cast<std::size_t>(n));
  face_.resize(static_cast<std::size_t>(n));
  for (int s = 0; s < n; ++s) {
    face_[s] = items[s].second;
    tris_[s] = unsorted[items[s].second];
  }

  struct Task {
    int node, begin, end;
  };
  nodes_.reserve(2 * static_cast<std::size_t>(n));
  nodes_.push_back({});
  std::vector<Task> tasks{{0, 0, n}};
  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    Node& node = nodes_[task.node];
    node.first = task.begin;
    node.count = task.end - task.begin;
    if (node.count <= kLeafSize) continue;
    const std::uint64_t a = items[task.begin].first, b = items[task.end - 1].first;
    int mid = task.begin + node.count / 2;
    if (a != b) {  // first code with the highest differing bit set
      const std::uint64_t bit = std::uint64_t{1} << (63 - std::countl_zero(a ^ b));
      mid = static_cast<int>(std::partition_point(items.begin() + task.begin, items.begin() + task.end,
                                                  [&](const auto& it) { return (it.first & bit) == 0; }) -
                             items.begin());
    }
    const int left = static_cast<int>(nodes_.size());
    node.first = left;
    node.count = 0;
    nodes_.push_back({});
    nodes_.push_back({});
    tasks.push_back({left, task.begin, mid});
    tasks.push_back({left + 1, mid, task.end});
  }
  refit_boxes();
}

void Bvh::set_positions(const VertexData<Vec3>& positions) {
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!positions.raw()[i].allFinite())
      throw InvalidInput("BVH: the position of vertex " + std::to_string(i) + " is not finite");
  pos_ = positions.raw();
}

void Bvh::refit(const VertexData<Vec3>& positions) {
  if (positions.size() != pos_.size())
    throw InvalidInput("BVH refit: got " + std::to_string(positions.size()) + " positions, the tree was built for " +
                       std::to_string(pos_.size()) + " (rebuild it after changing the mesh)");
  set_positions(positions);
  refit_boxes();
}

void Bvh::refit_boxes() {
  for (int i = n_nodes() - 1; i >= 0; --i) {  // children always follow their parent
    Node& node = nodes_[i];
    Box box;
    if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s)
        for (int k = 0; k < 3; ++k) box.grow(pos_[tris_[s][k]].data());
    } else {
      for (const Node* c : {&nodes_[node.first], &nodes_[node.first + 1]})
        for (int a = 0; a < 3; ++a) {
          box.lo[a] = std::min(box.lo[a], c->lo[a]);
          box.hi[a] = std::max(box.hi[a], c->hi[a]);
        }
    }
    std::copy(box.lo, box.lo + 3, node.lo);
    std::copy(box.hi, box.hi + 3, node.hi);
  }
}

Vec3 Bvh::bounds_min() const { return nodes_.empty() ? Vec3::Zero() : Vec3(nodes_[0].lo[0], nodes_[0].lo[1], nodes_[0].lo[2]); }
Vec3 Bvh::bounds_max() const { return nodes_.empty() ? Vec3::Zero() : Vec3(nodes_[0].hi[0], nodes_[0].hi[1], nodes_[0].hi[2]); }

// Near-child-first traversal. visit(slot_begin, slot_end, t_max) tests a leaf, may lower t_max,
// and returns true to stop.
template <class Visit>
void Bvh::traverse(const Ray& ray, double& t_max, Visit&& visit) const {
  if (nodes_.empty()) return;
  const double o[3] = {ray.origin.x(), ray.origin.y(), ray.origin.z()};
  const double inv[3] = {1.0 / ray.direction.x(), 1.0 / ray.direction.y(), 1.0 / ray.direction.z()};
  // Axes the ray runs parallel to (a zero or subnormal component): the slab test would give
  // 0 * inf = NaN for an origin on a box face, so test the origin against the slab instead.
  const bool parallel[3] = {!std::isfinite(inv[0]), !std::isfinite(inv[1]), !std::isfinite(inv[2])};
  // Entry distance of the ray into a node's box, or +inf if it misses within (0, t_max).
  auto enter = [&](const Node& n) {
    double t0 = 0.0, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
      if (parallel[a]) {
        if (o[a] < n.lo[a] || o[a] > n.hi[a]) return kInf;
        continue;
      }
      double tn = (n.lo[a] - o[a]) * inv[a], tf = (n.hi[a] - o[a]) * inv[a];
      if (tn > tf) std::swap(tn, tf);
      tf *= kExitScale;
      t0 = tn > t0 ? tn : t0;
      t1 = tf < t1 ? tf : t1;
      if (t0 > t1) return kInf;
    }
    return t0;
  };
  struct Entry {
    int node;
    double t;  // where the ray enters the node's box
  };
  Entry stack[kStackSize];
  int top = 0;
  if (const double t = enter(nodes_[0]); t != kInf) stack[top++] = {0, t};
  while (top > 0) {
    const Entry e = stack[--top];
    if (!(e.t < t_max)) continue;  // a closer hit was found since it was pushed
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      if (visit(node.first, node.first + node.count, t_max)) return;
      continue;
    }
    const double ta = enter(nodes_[node.first]), tb = enter(nodes_[node.first + 1]);
    // Push the far child first so the near one is visited next.
    const bool a_first = ta <= tb;
    const Entry near{a_first ? node.first : node.first + 1, a_first ? ta : tb};
    const Entry far{a_first ? node.first + 1 : node.first, a_first ? tb : ta};
    if (far.t != kInf) stack[top++] = far;
    if (near.t != kInf) stack[top++] = near;
  }
}

std::optional<RayHit> Bvh::intersect(const Ray& ray, double t_max) const {
  std::optional<RayHit> best;
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  traverse(ray, t_max, [&](int begin, int end, double& limit) {
    for (int s = begin; s < end; ++s) {
      const auto& tri = tris_[s];
      double t, u, v;
      if (hit_triangle(o, d, pos_[tri[0]], pos_[tri[1]], pos_[tri[2]], limit, t, u, v)) {
        limit = t;
        best = RayHit{Face(face_[s]), t, Vec3(1.0 - u - v, u, v)};
      }
    }
    return false;
  });
  return best;
}

bool Bvh::occluded(const Ray& ray, double t_max, Vertex ignore) const {
  bool hit = false;
  const int skip = ignore.idx();
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  traverse(ray, t_max, [&](int begin, int end, double& limit) {
    for (int s = begin; s < end; ++s) {
      const auto& tri = tris_[s];
      if (tri[0] == skip || tri[1] == skip || tri[2] == skip) continue;
      double t, u, v;
      if (hit_triangle(o, d, pos_[tri[0]], pos_[tri[1]], pos_[tri[2]], limit, t, u, v)) return hit = true;
    }
    return false;
  });
  return hit;
}

}  // namespace freeform::editor
