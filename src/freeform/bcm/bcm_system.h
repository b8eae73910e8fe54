// Assembly of the BCM linear system (DESIGN.md section 3) on the k-ring neighbourhood of the
// free vertices only, so cost follows the support size, not the mesh size.
//
//   S_k = L * Lam_{k-1} D L * ... * Lam_1 D L          (rows of the free vertices)
//   A   = (-1)^k S_k, split by columns into free (A_pp) and constrained (A_pc) vertices.
// The sign makes A_pp positive (semi)definite when it is symmetric.
#pragma once

#include "freeform/bcm/settings.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <Eigen/SparseCore>

#include <vector>

namespace freeform {

struct BcmSystem {
  std::vector<Vertex> free;         // P: row and column order of A_pp (= regions.free_vertices())
  std::vector<Vertex> constrained;  // C: constrained vertices within k rings of the free ones
  Eigen::SparseMatrix<double> a_pp;  // P by P
  Eigen::SparseMatrix<double> a_pc;  // P by C
  bool symmetric = false;            // checked numerically (is_symmetric), never assumed
  int degenerate_faces = 0;          // operator diagnostics on the assembled faces
  int clamped_cotangents = 0;
};

// Throws InvalidInput (settings out of range) or InvalidInput naming a vertex if a connected
// part of the free region has no constraint within reach (the system would be singular).
// `positions`: where cotangents and areas come from (the rest shape; for anisotropic bending
// a parametrization embedded in z = 0).
BcmSystem assemble_bcm_system(const Mesh& mesh, const VertexData<Vec3>& positions, const Regions& regions,
                              const BcmSettings& settings);

}  // namespace freeform
