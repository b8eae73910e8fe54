// The local numbering the BCM system's assembly and its ordering ahead share: the free vertices
// first (in the order given), then the vertices around them ring by ring, in the order a
// breadth-first walk meets them. Loops over local indices read compact arrays instead of the
// mesh's (a subdivided mesh's numbering scatters neighbours).
#pragma once

#include "freeform/mesh/mesh.h"

#include <vector>

namespace freeform {

struct Patch {
  std::vector<Vertex> order;  // local index -> vertex
  std::vector<int> dist;      // ring distance from the free set
  VertexData<int> local;      // vertex -> local index, -1 outside
  int n_free = 0;
  int n_inner = 0;  // local indices [0, n_inner) have ring distance <= k-1 (-1 for k = 0)
};

// The free vertices and those within k >= 0 rings of them.
Patch build_patch(const Mesh& mesh, const std::vector<Vertex>& free, int k);

}  // namespace freeform
