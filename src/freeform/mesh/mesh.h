// Halfedge triangle mesh with double positions.
//
// Storage is flat arrays: halfedges 2e and 2e+1 form edge e and are each other's opposite.
// Every halfedge has next/prev; mesh-boundary halfedges have no face and are linked around
// their boundary loop. A boundary vertex's halfedge() is its outgoing boundary halfedge, so
// circulation around any vertex visits its whole (single) fan.
//
// A Mesh is always 2-manifold with consistent orientation; input that is not is refused by
// from_soup (TopologyError naming the elements) or, with BuildOptions::repair, made manifold
// by splitting vertices (reported in BuildReport). Vertex i of the soup is vertex i of the mesh.
#pragma once

#include "freeform/mesh/attributes.h"
#include "freeform/mesh/handles.h"
#include "freeform/mesh/types.h"

#include <array>
#include <string>
#include <vector>

namespace freeform {

struct BuildOptions {
  // false: refuse non-representable input with a TopologyError.
  // true: split vertices at non-manifold edges/vertices, drop faces with a repeated index.
  bool repair = false;
};

// What from_soup changed (only with repair).
struct BuildReport {
  int dropped_faces = 0;      // faces with a repeated vertex index
  int split_vertices = 0;     // original vertices that were split into several
  int added_vertices = 0;     // new vertices created by splitting (appended after the originals)
  std::vector<int> origin;    // for each added vertex (index n_original + i): the vertex it copies
  std::vector<int> face_origin;      // with repair: for each face of the mesh, its face in the soup
  std::vector<std::string> changes;  // one human-readable line per change (capped)
  bool changed() const { return dropped_faces > 0 || added_vertices > 0; }
};

template <class H>
class HandleRange {
 public:
  struct iterator {
    int i;
    H operator*() const { return H(i); }
    iterator& operator++() { ++i; return *this; }
    bool operator==(const iterator&) const = default;
  };
  explicit HandleRange(int n) : n_(n) {}
  iterator begin() const { return {0}; }
  iterator end() const { return {n_}; }

 private:
  int n_;
};

class Mesh;

// Outgoing halfedges of a vertex, in rotation order; empty for an isolated vertex.
class HalfedgesAroundVertex {
 public:
  struct iterator {
    const Mesh* mesh;
    Halfedge h;
    bool moved;
    Halfedge operator*() const { return h; }
    iterator& operator++();
    bool operator==(const iterator& o) const { return h == o.h && moved == o.moved; }
  };
  HalfedgesAroundVertex(const Mesh& m, Vertex v);
  iterator begin() const { return {mesh_, start_, !start_.is_valid()}; }
  iterator end() const { return {mesh_, start_, true}; }

 private:
  const Mesh* mesh_;
  Halfedge start_;
};

class Mesh {
 public:
  Mesh() = default;

  // Builds connectivity from a soup. Preconditions checked (TopologyError / InvalidInput):
  // indices in range, positions finite. Cost O(#faces) with small per-vertex lists.
  static Mesh from_soup(const TriangleSoup& soup, const BuildOptions& options = {}, BuildReport* report = nullptr);
  TriangleSoup to_soup() const;

  int n_vertices() const { return static_cast<int>(v_halfedge_.size()); }
  int n_faces() const { return static_cast<int>(f_halfedge_.size()); }
  int n_edges() const { return static_cast<int>(he_to_.size() / 2); }
  int n_halfedges() const { return static_cast<int>(he_to_.size()); }

  HandleRange<Vertex> vertices() const { return HandleRange<Vertex>(n_vertices()); }
  HandleRange<Face> faces() const { return HandleRange<Face>(n_faces()); }
  HandleRange<Edge> edges() const { return HandleRange<Edge>(n_edges()); }
  HandleRange<Halfedge> halfedges() const { return HandleRange<Halfedge>(n_halfedges()); }

  // --- connectivity ---
  Halfedge halfedge(Vertex v) const { return v_halfedge_[v]; }  // outgoing; invalid if isolated
  Halfedge halfedge(Face f) const { return f_halfedge_[f]; }
  Halfedge halfedge(Edge e, int i) const { return Halfedge(2 * e.idx() + i); }  // i in {0,1}
  Vertex to_vertex(Halfedge h) const { return he_to_[h]; }
  Vertex from_vertex(Halfedge h) const { return he_to_[opposite(h)]; }
  Halfedge next(Halfedge h) const { return he_next_[h]; }
  Halfedge prev(Halfedge h) const { return he_prev_[h]; }
  Halfedge opposite(Halfedge h) const { return Halfedge(h.idx() ^ 1); }
  Halfedge ccw_rotated(Halfedge h) const { return opposite(prev(h)); }  // next outgoing, ccw
  Halfedge cw_rotated(Halfedge h) const { return next(opposite(h)); }   // next outgoing, cw
  Edge edge(Halfedge h) const { return Edge(h.idx() >> 1); }
  Face face(Halfedge h) const { return he_face_[h]; }  // invalid for a boundary halfedge
  std::array<Vertex, 3> vertices(Face f) const;
  std::array<Halfedge, 3> halfedges(Face f) const;

  bool is_boundary(Halfedge h) const { return !face(h).is_valid(); }
  bool is_boundary(Edge e) const { return is_boundary(halfedge(e, 0)) || is_boundary(halfedge(e, 1)); }
  bool is_boundary(Vertex v) const { return v_halfedge_[v].is_valid() && is_boundary(v_halfedge_[v]); }
  bool is_isolated(Vertex v) const { return !v_halfedge_[v].is_valid(); }
  int valence(Vertex v) const;
  // Halfedge from a to b, or invalid.
  Halfedge find_halfedge(Vertex a, Vertex b) const;

  HalfedgesAroundVertex outgoing(Vertex v) const { return HalfedgesAroundVertex(*this, v); }

  // --- geometry ---
  const Vec3& position(Vertex v) const { return positions_[v]; }
  Vec3& position(Vertex v) { return positions_[v]; }
  const VertexData<Vec3>& positions() const { return positions_; }
  VertexData<Vec3>& positions() { return positions_; }

  // #V by 3 copy of the positions (explicit conversion at the numerical boundary).
  Eigen::MatrixX3d position_matrix() const;
  // Overwrite positions from a #V by 3 matrix.
  void set_positions(const Eigen::MatrixX3d& x);

 private:
  VertexData<Vec3> positions_;
  VertexData<Halfedge> v_halfedge_;
  FaceData<Halfedge> f_halfedge_;
  HalfedgeData<Vertex> he_to_;
  HalfedgeData<Halfedge> he_next_;
  HalfedgeData<Halfedge> he_prev_;
  HalfedgeData<Face> he_face_;
};

}  // namespace freeform
