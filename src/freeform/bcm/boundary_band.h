// Where boundary smoothness acts (docs/bcm.md): the constrained vertices whose
// lambda weights enter the BCM rows, and the c of every vertex as the system uses it.
#pragma once

#include "freeform/bcm/settings.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <vector>

namespace freeform {

// Fixed and handle vertices within k-1 edge rings of a free vertex (k = order), sorted. Only
// their c changes the result: ring k enters the rows as values, not as Laplacian rows. Empty
// for k = 1 (a membrane is always C0).
std::vector<Vertex> smoothness_band(const Mesh& mesh, const Regions& regions, int order);

// c per vertex: k-1 on free vertices, outer / inner on fixed / handle vertices, then the
// segments in order (later ones win; their free vertices are skipped). Settings must be
// valid (validate_settings) and segment vertices inside the regions' mesh.
std::vector<double> smoothness_per_vertex(const Regions& regions, const BcmSettings& settings);

}  // namespace freeform
