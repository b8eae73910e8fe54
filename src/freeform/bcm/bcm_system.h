// Assembly of the BCM linear system (docs/bcm.md) on the k-ring neighbourhood of the
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
  std::vector<Vertex> free;         // P: row and column order of A_pp (regions.free_vertices() breadth-first)
  std::vector<Vertex> constrained;  // C: constrained vertices within k rings of the free ones,
                                    //    ring by ring (column order of A_pc)
  Eigen::SparseMatrix<double> a_pp;  // P by P (structural zeros from lambda = 0 kept)
  Eigen::SparseMatrix<double> a_pc;  // P by C (exact zeros dropped)
  bool symmetric = false;            // checked numerically (is_symmetric), never assumed
  int degenerate_faces = 0;          // operator diagnostics on the assembled faces
  std::vector<int> degenerate_examples;  // the first few of them (face indices), for messages
  int clamped_cotangents = 0;
  int zero_area_vertices = 0;        // rows whose area was floored (as in mixed_voronoi_areas)
  // lap: the cotangent Laplacian rows of the (k-1)-ring (free first, then constrained, as in
  // `constrained`) over the whole patch (free, then constrained columns). outer (only with
  // split_operator, the nonlinear model): P by those rows, sign included, so that
  // [a_pp a_pc] = outer * lap. k = 1: -I.
  Eigen::SparseMatrix<double, Eigen::RowMajor> lap;
  Eigen::SparseMatrix<double> outer;
  // The unassembled factors, for the refinement (bcm/refinement.h): lap (always filled) and
  // the diagonal weights Lam_m D of levels m = 1 .. k-1 on the (k-1)-ring rows. ring_rows[r]:
  // patch vertices within r rings of the free set (r = 0 .. k; the patch is ordered by ring).
  std::vector<Eigen::VectorXd> level_weights;
  std::vector<int> ring_rows;
};

// Cost: O(size of the k-ring of the free set) plus O(#V + #F) for index arrays. Cotangents
// and mixed areas come only from the faces incident to the (k-1)-ring (same degenerate-face
// policy as operators.h). Smoothness segments on free vertices are ignored.
// Throws InvalidInput (settings out of range, regions or positions of another size, a
// non-finite position in the patch, a segment naming a vertex outside the mesh) or
// InvalidInput naming a vertex if a connected part of the free region (through free-free
// edges) has no constrained vertex in its one-ring (the system would be singular).
// `positions`: where cotangents and areas come from (the rest shape; for anisotropic bending
// a parametrization embedded in z = 0).
BcmSystem assemble_bcm_system(const Mesh& mesh, const VertexData<Vec3>& positions, const Regions& regions,
                              const BcmSettings& settings, bool split_operator = false);

}  // namespace freeform
