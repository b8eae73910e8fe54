#include "viewer/geometry_patch.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <limits>

namespace freeform::viewer {

GeometryPatch::GeometryPatch(const RenderScene& scene, std::span<const Vertex> moving)
    : n_vertices_(scene.n_vertices()), n_triangles_(scene.n_triangles()) {
  const auto nv = static_cast<std::size_t>(n_vertices_);
  std::vector<char> moves(nv, 0), normal(nv, 0);
  for (Vertex v : moving) {
    if (v.idx() < 0 || v.idx() >= n_vertices_)
      throw InvalidInput("geometry patch: vertex " + std::to_string(v.idx()) + " is outside the scene");
    moves[static_cast<std::size_t>(v.idx())] = 1;
  }
  for (std::uint32_t v = 0; v < nv; ++v)
    if (moves[v]) moving_.push_back(v);
  if (moving_.empty()) return;
  // Every corner of a triangle with a moving corner needs its normal again.
  const std::vector<std::uint32_t>& tri = scene.triangles;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3)
    if (moves[tri[t]] || moves[tri[t + 1]] || moves[tri[t + 2]])
      for (std::size_t k = 0; k < 3; ++k) normal[tri[t + k]] = 1;
  std::vector<int> slot(nv, -1);
  for (std::uint32_t v = 0; v < nv; ++v)
    if (normal[v]) {
      slot[v] = static_cast<int>(normal_vertices_.size());
      normal_vertices_.push_back(v);
    }
  // The triangles around them (moving or not), each computed once per frame; per normal
  // vertex its triangles in ascending order, the order make_scene sums them in.
  offset_.assign(normal_vertices_.size() + 1, 0);
  std::vector<int> local;  // triangle -> index in triangles_
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    if (slot[tri[t]] < 0 && slot[tri[t + 1]] < 0 && slot[tri[t + 2]] < 0) continue;
    local.push_back(static_cast<int>(triangles_.size() / 3));
    triangles_.insert(triangles_.end(), {tri[t], tri[t + 1], tri[t + 2]});
    for (std::size_t k = 0; k < 3; ++k)
      if (slot[tri[t + k]] >= 0) ++offset_[static_cast<std::size_t>(slot[tri[t + k]]) + 1];
  }
  for (std::size_t i = 1; i < offset_.size(); ++i) offset_[i] += offset_[i - 1];
  incident_.resize(static_cast<std::size_t>(offset_.back()));
  std::vector<int> fill(offset_.begin(), offset_.end() - 1);
  for (std::size_t j = 0; j < triangles_.size(); ++j)
    if (const int sl = slot[triangles_[j]]; sl >= 0) incident_[static_cast<std::size_t>(fill[static_cast<std::size_t>(sl)]++)] = static_cast<int>(j / 3);
  triangle_normal_.resize(triangles_.size());
  static_bounds_ = empty_box();
  for (std::size_t v = 0; v < nv; ++v)
    if (!moves[v]) extend(static_bounds_, &scene.positions[3 * v]);
  // Upload ranges: runs of normal vertices, the closest ones merged until kMaxRanges remain.
  for (const std::uint32_t v : normal_vertices_) {
    if (!ranges_.empty() && ranges_.back().first + ranges_.back().second == static_cast<int>(v))
      ++ranges_.back().second;
    else
      ranges_.emplace_back(static_cast<int>(v), 1);
  }
  while (ranges_.size() > static_cast<std::size_t>(kMaxRanges)) {
    std::size_t best = 0;
    int best_gap = std::numeric_limits<int>::max();
    for (std::size_t i = 0; i + 1 < ranges_.size(); ++i) {
      const int gap = ranges_[i + 1].first - (ranges_[i].first + ranges_[i].second);
      if (gap < best_gap) best_gap = gap, best = i;
    }
    ranges_[best].second = ranges_[best + 1].first + ranges_[best + 1].second - ranges_[best].first;
    ranges_.erase(ranges_.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  }
}

int GeometryPatch::range_vertices() const {
  int n = 0;
  for (const auto& r : ranges_) n += r.second;
  return n;
}

void GeometryPatch::apply(RenderScene& scene, const VertexData<Vec3>& positions) const {
  if (scene.n_vertices() != n_vertices_ || scene.n_triangles() != n_triangles_ ||
      positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("geometry patch: the scene or the positions are not the ones the patch was built for");
  BoundingBox box = static_bounds_;
  for (const std::uint32_t v : moving_) {
    const Vec3& q = positions[Vertex(static_cast<int>(v))];
    float* p = &scene.positions[3 * static_cast<std::size_t>(v)];
    for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(q[k]);
    extend(box, p);
  }
  scene.bounds = box;
  const float* p = scene.positions.data();
  for (std::size_t j = 0; j < triangles_.size(); j += 3) {
    const Eigen::Vector3f n = triangle_normal(p, &triangles_[j]);
    for (int k = 0; k < 3; ++k) triangle_normal_[j + static_cast<std::size_t>(k)] = n[k];
  }
  for (std::size_t i = 0; i < normal_vertices_.size(); ++i) {
    float* n = &scene.normals[3 * static_cast<std::size_t>(normal_vertices_[i])];
    n[0] = n[1] = n[2] = 0.0f;
    for (int j = offset_[i]; j < offset_[i + 1]; ++j)
      add3(n, Eigen::Vector3f::Map(&triangle_normal_[3 * static_cast<std::size_t>(incident_[static_cast<std::size_t>(j)])]));
    normalize3(n);
  }
}

}  // namespace freeform::viewer
