// Neighbourhoods and global structure of a Mesh: one-rings, k-rings, boundary loops,
// connected components.
#pragma once

#include "freeform/mesh/mesh.h"

#include <span>
#include <vector>

namespace freeform {

// Neighbours of v in rotation order (empty for an isolated vertex).
std::vector<Vertex> one_ring(const Mesh& mesh, Vertex v);

// Ring distance (edge hops) from the nearest seed, -1 beyond max_k. Seeds have 0.
VertexData<int> ring_distance(const Mesh& mesh, std::span<const Vertex> seeds, int max_k);

// All vertices within k rings of the seeds (seeds included), in breadth-first order.
std::vector<Vertex> k_ring(const Mesh& mesh, std::span<const Vertex> seeds, int k);

// Each boundary loop as its boundary halfedges in order (next() links them).
std::vector<std::vector<Halfedge>> boundary_loops(const Mesh& mesh);

struct Components {
  VertexData<int> vertex_component;  // component id of each vertex
  FaceData<int> face_component;      // component id of each face
  int count = 0;                     // isolated vertices count as components of their own
};

// Components connected through edges, numbered in order of their smallest vertex.
Components connected_components(const Mesh& mesh);

// Component ids of the pieces of a vertex set connected through edges between its vertices
// (in[v] != 0; `in` has #V entries), numbered in order of their smallest vertex; -1 outside
// the set. `count` receives the number of pieces.
VertexData<int> label_pieces(const Mesh& mesh, std::span<const char> in, int& count);

// The vertex set `set` (distinct vertices) reordered breadth-first through edges between its
// vertices, each piece started at its first vertex in `set`. Neighbours end up near each other
// in arrays indexed this way: a mesh whose numbering scatters neighbours (subdivided ones
// number edge midpoints after all old vertices) made per-vertex loops latency-bound. Each piece
// is a contiguous run of the result; piece_starts (optional) receives where each run begins.
std::vector<Vertex> breadth_first_order(const Mesh& mesh, std::span<const Vertex> set,
                                        std::vector<int>* piece_starts = nullptr);

}  // namespace freeform
