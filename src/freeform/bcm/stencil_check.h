// Refuses supports whose order-k operator would hold a row of more than kMaxStencil vertices: one
// vertex of huge valence near the free region (a polygon of a million corners fanned around one
// of them) would make rows of that size around it, and memory and the factorization grow with
// its square and cube. Fans of a few thousand needles (CAD parts' discs, triangulated files'
// caps) stay below it where the rows really are that small.
#pragma once

#include "freeform/mesh/mesh.h"

#include <vector>

namespace freeform {

// Above this many vertices in one row of the order-k operator (the k-ring of a free vertex) an
// edit is refused: a dense block of that size takes seconds to factor. A regular mesh has 19
// (k = 2) or 37 (k = 3); real meshes stay below a few hundred.
inline constexpr long kMaxStencil = 4096;

// Throws InvalidInput naming the highest valence within k - 1 rings of the first free vertex (in
// the order of `free`) whose k-ring holds more than kMaxStencil vertices. Cheap bounds (sums of
// valences) pass most vertices; those near high valences have their k-ring counted, stopping
// past the limit.
void check_stencil_size(const Mesh& mesh, const std::vector<Vertex>& free, int k);

}  // namespace freeform
