// An independent reference for the order-k BCM solve at any size (issue 13), written from
// docs/bcm.md with none of the library's assembly or solvers: the global cotangent
// Laplacian and mixed areas (operators.h), the intermediate Laplacians as unknowns of their own
// (the mixed form, so no block is worse conditioned than a Laplacian), Eigen's SparseLU (the
// library factors the assembled product with CHOLMOD or UMFPACK) and two steps of iterative
// refinement. No gtest: the accuracy benchmark uses it too.
//
//   2 A_v u_1(v) - lam_1(c_v) (L x)_v           = 0   v within k-1 rings of the free set
//   2 A_v u_m(v) - lam_m(c_v) (L u_{m-1})_v     = 0   v within k-m rings, m = 2 .. k-1
//   (L u_{k-1})_v                                = 0   v free (k = 1: (L x)_v = 0)
#pragma once

#include "freeform/mesh/traversal.h"
#include "freeform/operators/operators.h"
#include "freeform/regions/regions.h"

#include <Eigen/SparseLU>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace freeform::test {

// Free positions (row i = regions.free_vertices()[i]) with every other vertex at `boundary`.
// c_outer / c_inner: boundary smoothness of fixed / handle vertices (free ones have k-1).
inline Eigen::MatrixXd mixed_form_reference(const Mesh& mesh, const Regions& regions, int k,
                                            const VertexData<Vec3>& boundary, double c_outer, double c_inner) {
  const Eigen::SparseMatrix<double> lap = cotan_laplacian(mesh);
  const Eigen::VectorXd area = mixed_voronoi_areas(mesh);
  const std::vector<Vertex>& free = regions.free_vertices();
  const VertexData<int> dist = ring_distance(mesh, free, k);
  const auto lambda = [&](Vertex v, int m) {
    const double c = regions.role(v) == Role::Free ? k - 1.0 : regions.role(v) == Role::Fixed ? c_outer : c_inner;
    return std::clamp(c - m + 1.0, 0.0, 1.0);
  };
  // Block b = 0 is x on the free set; block m = 1 .. k-1 is u_m within k-m rings.
  std::vector<VertexData<int>> index;
  std::vector<int> offset{0};
  for (int b = 0; b < k; ++b) {
    const int within = b == 0 ? 0 : k - b;
    VertexData<int>& idx = index.emplace_back(static_cast<std::size_t>(mesh.n_vertices()), -1);
    int n = 0;
    for (Vertex v : mesh.vertices())
      if (dist[v] >= 0 && dist[v] <= within) idx[v] = offset.back() + n++;
    offset.push_back(offset.back() + n);
  }
  const int n = offset.back();
  std::vector<Eigen::Triplet<double>> t;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  // Row of equation block m (m = 1 .. k-1: u_m's definition; m = k: the free rows) for v: the
  // unknowns of u_m share its numbering, the free rows that of x.
  for (int m = 1; m <= k; ++m) {
    const VertexData<int>& rows = index[static_cast<std::size_t>(m < k ? m : 0)];
    const VertexData<int>& prev = index[static_cast<std::size_t>(m - 1)];
    for (Vertex v : mesh.vertices()) {
      const int r = rows[v];
      if (r < 0) continue;
      const double lam = m < k ? lambda(v, m) : 1.0;
      if (m < k) t.emplace_back(r, r, 2.0 * area[v.idx()]);
      for (Eigen::SparseMatrix<double>::InnerIterator it(lap, v.idx()); it; ++it) {  // L symmetric
        const Vertex u(static_cast<int>(it.row()));
        const double coef = -lam * it.value();
        if (prev[u] >= 0)
          t.emplace_back(r, prev[u], coef);
        else if (m == 1)
          rhs.row(r) -= coef * boundary[u].transpose();
        else
          throw std::logic_error("mixed_form_reference: a stencil left its rings");
      }
    }
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(a);
  if (lu.info() != Eigen::Success) throw std::runtime_error("mixed_form_reference: SparseLU failed");
  Eigen::MatrixXd x = lu.solve(rhs);
  for (int step = 0; step < 2; ++step) x += lu.solve(rhs - a * x);
  Eigen::MatrixXd out(free.size(), 3);
  for (std::size_t i = 0; i < free.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = x.row(index[0][free[i]]);
  return out;
}

}  // namespace freeform::test
