#include "freeform/mesh/traversal.h"

#include "freeform/common/error.h"

namespace freeform {

std::vector<Vertex> one_ring(const Mesh& mesh, Vertex v) {
  std::vector<Vertex> ring;
  for (Halfedge h : mesh.outgoing(v)) ring.push_back(mesh.to_vertex(h));
  return ring;
}

VertexData<int> ring_distance(const Mesh& mesh, std::span<const Vertex> seeds, int max_k) {
  VertexData<int> dist(mesh.n_vertices(), -1);
  std::vector<Vertex> frontier;
  for (Vertex s : seeds) {
    if (s.idx() < 0 || s.idx() >= mesh.n_vertices()) throw InvalidInput("seed vertex " + std::to_string(s.idx()) + " is not in the mesh");
    if (dist[s] < 0) {
      dist[s] = 0;
      frontier.push_back(s);
    }
  }
  std::vector<Vertex> next;
  for (int k = 1; k <= max_k && !frontier.empty(); ++k) {
    next.clear();
    for (Vertex v : frontier)
      for (Halfedge h : mesh.outgoing(v)) {
        const Vertex w = mesh.to_vertex(h);
        if (dist[w] < 0) {
          dist[w] = k;
          next.push_back(w);
        }
      }
    frontier.swap(next);
  }
  return dist;
}

std::vector<Vertex> k_ring(const Mesh& mesh, std::span<const Vertex> seeds, int k) {
  const VertexData<int> dist = ring_distance(mesh, seeds, k);
  std::vector<std::vector<Vertex>> by_ring(static_cast<std::size_t>(k) + 1);
  for (Vertex v : mesh.vertices())
    if (dist[v] >= 0) by_ring[dist[v]].push_back(v);
  std::vector<Vertex> out;
  for (const auto& ring : by_ring) out.insert(out.end(), ring.begin(), ring.end());
  return out;
}

std::vector<std::vector<Halfedge>> boundary_loops(const Mesh& mesh) {
  std::vector<std::vector<Halfedge>> loops;
  HalfedgeData<char> seen(mesh.n_halfedges(), 0);
  for (Halfedge h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || seen[h]) continue;
    std::vector<Halfedge> loop;
    for (Halfedge g = h; !seen[g]; g = mesh.next(g)) {
      seen[g] = 1;
      loop.push_back(g);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

VertexData<int> label_pieces(const Mesh& mesh, std::span<const char> in, int& count) {
  VertexData<int> id(mesh.n_vertices(), -1);
  count = 0;
  std::vector<Vertex> stack;
  for (Vertex seed : mesh.vertices()) {
    if (id[seed] >= 0 || !in[static_cast<std::size_t>(seed.idx())]) continue;
    id[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Vertex v = stack.back();
      stack.pop_back();
      for (Halfedge h : mesh.outgoing(v)) {
        const Vertex w = mesh.to_vertex(h);
        if (id[w] < 0 && in[static_cast<std::size_t>(w.idx())]) {
          id[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return id;
}

Components connected_components(const Mesh& mesh) {
  Components c;
  const std::vector<char> all(static_cast<std::size_t>(mesh.n_vertices()), 1);
  c.vertex_component = label_pieces(mesh, all, c.count);
  c.face_component = FaceData<int>(mesh.n_faces(), -1);
  for (Face f : mesh.faces()) c.face_component[f] = c.vertex_component[mesh.vertices(f)[0]];
  return c;
}

std::vector<Vertex> breadth_first_order(const Mesh& mesh, std::span<const Vertex> set, std::vector<int>* piece_starts) {
  // 0 outside the set, 1 in it and not yet queued, 2 queued.
  VertexData<char> state(static_cast<std::size_t>(mesh.n_vertices()), 0);
  for (Vertex v : set) state[v] = 1;
  std::vector<Vertex> out;
  out.reserve(set.size());
  if (piece_starts) piece_starts->clear();
  for (Vertex start : set) {
    if (state[start] != 1) continue;
    state[start] = 2;
    std::size_t head = out.size();
    if (piece_starts) piece_starts->push_back(static_cast<int>(head));
    out.push_back(start);
    for (; head < out.size(); ++head)
      for (Halfedge h : mesh.outgoing(out[head]))
        if (const Vertex w = mesh.to_vertex(h); state[w] == 1) {
          state[w] = 2;
          out.push_back(w);
        }
  }
  return out;
}

}  // namespace freeform
