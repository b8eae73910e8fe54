// Internal: how the triangles of a soup glue together along edges and around vertices.
// Shared by Mesh::from_soup (which needs it to build or repair) and validate().
#pragma once

#include "freeform/mesh/types.h"

#include <array>
#include <vector>

namespace freeform::detail {

// Directed face edge d = 3f + i runs from faces[f][i] to faces[f][(i+1)%3]; corner 3f + i sits
// at faces[f][i]. Faces must not repeat an index within themselves.
struct SoupTopology {
  std::vector<int> twin;  // 3F: the glued directed edge of the neighbour face, or -1
  std::vector<std::array<int, 2>> nonmanifold_edges;   // vertex pairs used by more than two faces
  std::vector<std::array<int, 2>> inconsistent_edges;  // two faces traverse it in the same direction
  std::vector<int> fan;       // 3F: for each corner, the fan (0-based, per vertex) it belongs to
  std::vector<int> fan_count; // #V: number of fans per vertex (0 if unreferenced)
};

// Glues the directed edges of `faces` (every index in [0, n_vertices)). An undirected edge is
// glued only if exactly two faces use it in opposite directions; fans are the groups of
// corners at a vertex that are connected across glued edges. O(F) time and memory.
SoupTopology analyze_soup(int n_vertices, const std::vector<Tri>& faces);

// True if the face repeats an index.
inline bool has_repeated_index(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

}  // namespace freeform::detail
