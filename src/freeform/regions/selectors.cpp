#include "freeform/regions/selectors.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>

namespace freeform {
namespace {

using json_messages::num;

// |a - b| without overflow or underflow of the squares (coordinates of 1e+-200).
double distance(const Vec3& a, const Vec3& b) {
  const Vec3 d = a - b;
  const double m = d.cwiseAbs().maxCoeff();
  if (!(m > 1e-150 && m < 1e150)) return m > 0.0 && std::isfinite(m) ? m * (d / m).norm() : m;
  return d.norm();
}

void check_ball(const Vec3& center, double radius, const std::string& name) {
  if (!center.allFinite()) throw InvalidInput(name + ": the center is not finite");
  if (!std::isfinite(radius) || radius <= 0.0)
    throw InvalidInput(name + ": the radius must be a finite number > 0, got " + num(radius));
}

std::vector<Vertex> nonempty(std::vector<Vertex> vs, const std::string& name, const std::string& why) {
  if (vs.empty()) throw InvalidInput(name + " selects no vertex (" + why + ")");
  return vs;
}

}  // namespace

std::vector<Vertex> select_indices(const Mesh& mesh, std::span<const long long> indices, const std::string& name) {
  if (indices.empty()) throw InvalidInput(name + " selects no vertex (empty vertex list)");
  std::vector<Vertex> out;
  out.reserve(indices.size());
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const long long idx = indices[i];
    if (idx < 0 || idx >= mesh.n_vertices())
      throw InvalidInput(name + ": vertex index " + std::to_string(idx) + " (entry " + std::to_string(i) +
                         ") is outside the mesh, which has vertices 0.." + std::to_string(mesh.n_vertices() - 1));
    out.emplace_back(static_cast<int>(idx));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<Vertex> select_sphere(const Mesh& mesh, const Vec3& center, double radius, const std::string& name) {
  check_ball(center, radius, name);
  std::vector<Vertex> out;
  for (Vertex v : mesh.vertices())
    if (distance(mesh.position(v), center) <= radius) out.push_back(v);
  return nonempty(std::move(out), name, "no vertex within distance " + num(radius) + " of the center");
}

Vertex nearest_vertex(const Mesh& mesh, const Vec3& p) {
  Vertex best;
  double best_d = std::numeric_limits<double>::infinity();
  for (Vertex v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    const double d = distance(mesh.position(v), p);
    if (d < best_d) {
      best_d = d;
      best = v;
    }
  }
  if (!best.is_valid())
    throw InvalidInput(p.allFinite() ? "the mesh has no faces, so no vertex lies on the surface"
                                     : "the point is not finite, so no vertex is nearest to it");
  return best;
}

VertexData<double> geodesic_distance(const Mesh& mesh, Vertex source, double max_distance) {
  return geodesic_distance(mesh, mesh.positions(), source, max_distance);
}

VertexData<double> geodesic_distance(const Mesh& mesh, const VertexData<Vec3>& positions, Vertex source,
                                     double max_distance, std::vector<Vertex>* reached) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!source.is_valid() || source.idx() >= mesh.n_vertices())
    throw InvalidInput("geodesic distance: source vertex " + std::to_string(source.idx()) + " is outside the mesh");
  if (positions.size() != static_cast<std::size_t>(mesh.n_vertices()))
    throw InvalidInput("geodesic distance: got " + std::to_string(positions.size()) + " positions for a mesh with " +
                       std::to_string(mesh.n_vertices()) + " vertices");
  VertexData<double> dist(mesh.n_vertices(), kInf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  dist[source] = 0.0;
  queue.emplace(0.0, source.idx());
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    const Vertex v(i);
    if (d > dist[v]) continue;  // stale entry
    if (reached) reached->push_back(v);
    for (Halfedge h : mesh.outgoing(v)) {
      const Vertex w = mesh.to_vertex(h);
      const double nd = d + distance(positions[w], positions[v]);
      if (nd < dist[w] && nd <= max_distance) {
        dist[w] = nd;
        queue.emplace(nd, w.idx());
      }
    }
  }
  return dist;
}

std::vector<Vertex> select_geodesic(const Mesh& mesh, const Vec3& center, double radius, const std::string& name) {
  check_ball(center, radius, name);
  Vertex source;
  try {
    source = nearest_vertex(mesh, center);
  } catch (const InvalidInput& e) {
    throw InvalidInput(name + ": " + e.what());
  }
  const VertexData<double> dist = geodesic_distance(mesh, source, radius);
  std::vector<Vertex> out;
  for (Vertex v : mesh.vertices())
    if (dist[v] <= radius) out.push_back(v);
  return out;  // never empty: the source itself has distance 0
}

std::vector<Vertex> select_labels(std::span<const int> labels, std::span<const int> wanted, const std::string& name) {
  if (wanted.empty()) throw InvalidInput(name + " selects no vertex (empty label list)");
  std::vector<Vertex> out;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (std::find(wanted.begin(), wanted.end(), labels[i]) != wanted.end()) out.emplace_back(static_cast<int>(i));
  std::string list;
  for (int w : wanted) list += (list.empty() ? "" : ", ") + std::to_string(w);
  return nonempty(std::move(out), name, "no vertex has label " + list);
}

}  // namespace freeform
