// Open seams: vertices on a boundary of the mesh at exactly the position of another boundary
// vertex. A file that splits its vertices (along texture seams, or a surface exported in
// patches) leaves the surface cut there, and an edit whose free vertices reach such a cut opens
// it: the two sides are solved apart.
#pragma once

#include "freeform/mesh/mesh.h"

#include <array>
#include <vector>

namespace freeform {

// The pairs (v, w), v among `vertices`, of boundary vertices at one position; each v once, with
// its first partner in index order.
std::vector<std::array<Vertex, 2>> open_seam_pairs(const Mesh& mesh, const std::vector<Vertex>& vertices);

}  // namespace freeform
