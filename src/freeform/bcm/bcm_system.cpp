// Local assembly of the BCM system (docs/operators.md, docs/bcm.md). Only the k-ring neighbourhood of
// the free vertices is touched: cotangents and mixed areas on the faces incident to the
// (k-1)-ring, then S_k = L Lam_{k-1} D L ... Lam_1 D L as sparse products on that patch.
#include "freeform/bcm/bcm_system.h"
#include "freeform/bcm/boundary_band.h"
#include "freeform/bcm/patch.h"
#include "freeform/bcm/stencil_check.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"
#include "freeform/mesh/traversal.h"
#include "freeform/numerics/csr.h"
#include "freeform/numerics/sparse_solver.h"
#include "freeform/operators/face_geometry.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>

namespace freeform {
namespace {

// A piece of the free region (connected through free-free edges: breadth_first_order's runs)
// with no constrained vertex in its one-ring makes A_pp singular: refuse it before factoring.
void check_constrained_reach(const Mesh& mesh, const Regions& regions, const std::vector<Vertex>& free,
                             const std::vector<int>& piece_starts) {
  std::vector<char> touches(free.size(), 0);
  parallel_for(static_cast<std::ptrdiff_t>(free.size()), 8192, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i)
      for (Halfedge h : mesh.outgoing(free[i]))
        if (regions.role(mesh.to_vertex(h)) != Role::Free) {
          touches[i] = 1;
          break;
        }
  });
  for (std::size_t c = 0; c < piece_starts.size(); ++c) {
    const auto first = touches.begin() + piece_starts[c];
    const auto last = c + 1 < piece_starts.size() ? touches.begin() + piece_starts[c + 1] : touches.end();
    if (std::find(first, last, 1) != last) continue;
    throw InvalidInput("the support covers a whole component of the mesh: free vertex " +
                       std::to_string(free[static_cast<std::size_t>(piece_starts[c])].idx()) +
                       " and the free vertices connected to it have no fixed or handle vertex next to them, so "
                       "their position is undetermined; add a handle or shrink the support");
  }
}

int row_count(const Patch& p, int max_dist) {
  int n = 0;
  while (n < static_cast<int>(p.dist.size()) && p.dist[static_cast<std::size_t>(n)] <= max_dist) ++n;
  return n;
}

// The inputs' consistency with the mesh (sizes, segment vertices).
void check_inputs(const Mesh& mesh, const VertexData<Vec3>& positions, const Regions& regions,
                  const BcmSettings& settings) {
  validate_settings(settings);
  const int nv = mesh.n_vertices();
  if (regions.n_vertices() != nv)
    throw InvalidInput("the regions were made for a mesh with " + std::to_string(regions.n_vertices()) +
                       " vertices, but this mesh has " + std::to_string(nv));
  if (positions.size() != static_cast<std::size_t>(nv))
    throw InvalidInput("assemble_bcm_system: positions have " + std::to_string(positions.size()) +
                       " entries but the mesh has " + std::to_string(nv) + " vertices");
  const auto& segments = settings.smoothness.segments;
  for (std::size_t i = 0; i < segments.size(); ++i)
    for (Vertex v : segments[i].vertices)
      if (v.idx() < 0 || v.idx() >= nv)
        throw InvalidInput("boundary smoothness segment " + std::to_string(i) + " names vertex " +
                           std::to_string(v.idx()) + ", but the mesh has " + std::to_string(nv) + " vertices");
}

// Per face incident to the (k-1)-ring: the cotangent opposite each of its three halfedges; per
// patch vertex its mixed area. Degenerate and clamped faces are counted into sys.
struct FaceWeights {
  FaceData<int> local_face;  // face -> index into cot, -1 outside
  std::vector<std::array<double, 3>, UninitializedAllocator<std::array<double, 3>>> cot;
  Eigen::VectorXd area;
  double total_area = 0.0;
};

// The faces incident to the (k-1)-ring in face order; local_face (all -1) receives their indices.
std::vector<Face> faces_around(const Mesh& mesh, const Patch& p, FaceData<int>& local_face) {
  parallel_for(p.n_inner, 8192, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i)
      for (Halfedge h : mesh.outgoing(p.order[i]))  // a face's corners may mark it at once
        if (const Face f = mesh.face(h); f.is_valid())
          std::atomic_ref<int>(local_face[f]).store(-2, std::memory_order_relaxed);
  });
  // Numbered in face order: each block counts its marked faces, then numbers them from its offset.
  const int n = mesh.n_faces();
  const int n_blocks = std::max(1, std::min(n / 65536, 4 * (parallel_workers() + 1)));
  auto first = [&](int b) { return static_cast<int>(static_cast<long>(n) * b / n_blocks); };
  std::vector<int> offset(static_cast<std::size_t>(n_blocks) + 1, 0);
  parallel_for(n_blocks, 1, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto b = static_cast<int>(begin); b < end; ++b)
      for (int f = first(b); f < first(b + 1); ++f)
        offset[static_cast<std::size_t>(b) + 1] += local_face[Face(f)] == -2;
  });
  for (std::size_t b = 0; b < static_cast<std::size_t>(n_blocks); ++b) offset[b + 1] += offset[b];
  std::vector<Face> faces(static_cast<std::size_t>(offset.back()));
  parallel_for(n_blocks, 1, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto b = static_cast<int>(begin); b < end; ++b) {
      int next = offset[static_cast<std::size_t>(b)];
      for (int f = first(b); f < first(b + 1); ++f)
        if (local_face[Face(f)] == -2) {
          local_face[Face(f)] = next;
          faces[static_cast<std::size_t>(next++)] = Face(f);
        }
    }
  });
  return faces;
}

FaceWeights face_weights(const Mesh& mesh, const VertexData<Vec3>& positions, const Patch& p, BcmSystem& sys) {
  FaceWeights out;
  out.local_face = FaceData<int>(static_cast<std::size_t>(mesh.n_faces()), -1);
  const std::vector<Face> faces = faces_around(mesh, p, out.local_face);
  // Filled by the parallel loop below, which then takes their pages' first touch (a serial
  // zeroing took longer than the loop at 1M free).
  std::vector<detail::CornerWeights, UninitializedAllocator<detail::CornerWeights>> weights(faces.size());
  out.cot.resize(faces.size());
  parallel_for(static_cast<std::ptrdiff_t>(faces.size()), 16384, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto fl = static_cast<std::size_t>(begin); fl < static_cast<std::size_t>(end); ++fl) {
      const detail::FaceCorners c = detail::face_corners(mesh, faces[fl]);
      weights[fl] = detail::corner_weights(positions[c.v[0]], positions[c.v[1]], positions[c.v[2]]);
      // face_corners: corner q lies opposite c.h[q], and c.h = (halfedge(f), next, next).
      out.cot[fl] = weights[fl].degenerate ? std::array<double, 3>{0.0, 0.0, 0.0} : weights[fl].cot;
    }
  });
  for (std::size_t fl = 0; fl < faces.size(); ++fl) {
    const detail::CornerWeights& w = weights[fl];
    if (w.degenerate) {
      if (++sys.degenerate_faces <= 5) sys.degenerate_examples.push_back(faces[fl].idx());
      continue;
    }
    sys.clamped_cotangents += w.clamped;
    for (const double a : w.area) out.total_area += a;
  }
  // Each vertex's area summed over its faces in face order (the bits of one loop over the faces).
  out.area.resize(static_cast<Eigen::Index>(p.order.size()));
  parallel_for(static_cast<std::ptrdiff_t>(p.order.size()), 8192, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    std::vector<std::pair<int, double>> corners;
    for (auto l = begin; l < end; ++l) {
      const Vertex v = p.order[static_cast<std::size_t>(l)];
      corners.clear();
      for (Halfedge h : mesh.outgoing(v)) {
        const Face f = mesh.face(h);
        if (!f.is_valid() || out.local_face[f] < 0) continue;
        const auto fl = static_cast<std::size_t>(out.local_face[f]);
        if (weights[fl].degenerate) continue;
        const detail::FaceCorners c = detail::face_corners(mesh, f);
        const std::size_t q = c.v[0] == v ? 0 : c.v[1] == v ? 1 : 2;
        corners.emplace_back(static_cast<int>(fl), weights[fl].area[q]);
      }
      std::sort(corners.begin(), corners.end());
      double sum = 0.0;
      for (const auto& [fl, a] : corners) sum += a;
      out.area[l] = sum;
    }
  });
  return out;
}

// L rows of the (k-1)-ring (columns: the whole patch), straight from the adjacency.
Csr laplacian_rows(const Mesh& mesh, const Patch& p, const FaceWeights& fw) {
  auto half_cot = [&](Halfedge h) {  // cotangent opposite h in its face (0 on the mesh boundary)
    const Face f = mesh.face(h);
    if (!f.is_valid()) return 0.0;
    const Halfedge h0 = mesh.halfedge(f);
    const int q = h == h0 ? 0 : h == mesh.next(h0) ? 1 : 2;
    return fw.cot[static_cast<std::size_t>(fw.local_face[f])][static_cast<std::size_t>(q)];
  };
  return build_csr(p.n_inner, static_cast<int>(p.order.size()), [&](int begin, int end, CsrBlock& out) {
    std::vector<std::pair<int, double>> row;
    for (int i = begin; i < end; ++i) {
      row.clear();
      double diagonal = 0.0;
      for (Halfedge h : mesh.outgoing(p.order[static_cast<std::size_t>(i)])) {
        const double wgt = half_cot(h) + half_cot(mesh.opposite(h));
        row.emplace_back(p.local[mesh.to_vertex(h)], wgt);
        diagonal -= wgt;
      }
      row.emplace_back(i, diagonal);
      std::sort(row.begin(), row.end());
      for (const auto& [col, v] : row) {
        out.inner.push_back(col);
        out.value.push_back(v);
      }
      out.row_end.push_back(static_cast<int>(out.inner.size()));
    }
  });
}

// Lam_m D of each level m = 1 .. k-1 over the (k-1)-ring (smoothness_lambda of each vertex's c
// over twice its floored area); counts the floored vertices into sys.
void level_weights(const Regions& regions, const BcmSettings& settings, const Patch& p, const FaceWeights& fw,
                   BcmSystem& sys) {
  const int n_inner = p.n_inner;
  std::vector<double> c(p.order.size());
  {
    const std::vector<double> c_global = smoothness_per_vertex(regions, settings);
    for (std::size_t i = 0; i < c.size(); ++i) c[i] = c_global[static_cast<std::size_t>(p.order[i].idx())];
  }
  // The floor of operators' mixed_voronoi_areas (kAreaFloorRatio of the mean vertex area), over
  // the patch; floored vertices are counted like there.
  const double area_floor =
      detail::kAreaFloorRatio * (n_inner > 0 && fw.total_area > 0.0 ? fw.total_area / n_inner : 1.0);
  for (int i = 0; i < n_inner; ++i) sys.zero_area_vertices += fw.area[i] >= area_floor ? 0 : 1;
  for (int m = 1; m <= settings.order - 1; ++m) {
    Eigen::VectorXd& w = sys.level_weights.emplace_back(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(c.size())));
    for (int i = 0; i < n_inner; ++i)
      w[i] = smoothness_lambda(c[static_cast<std::size_t>(i)], m) / (2.0 * std::max(fw.area[i], area_floor));
  }
}

}  // namespace

BcmSystem assemble_bcm_system(const Mesh& mesh, const VertexData<Vec3>& positions, const Regions& regions,
                              const BcmSettings& settings, bool split_operator) {
  check_inputs(mesh, positions, regions, settings);
  const int k = settings.order;
  BcmSystem sys;
  std::vector<int> piece_starts;
  sys.free = breadth_first_order(mesh, regions.free_vertices(), &piece_starts);
  check_stencil_size(mesh, sys.free, k);
  const Patch p = build_patch(mesh, sys.free, k);
  const int n_free = p.n_free;
  const int n_loc = static_cast<int>(p.order.size());
  const int n_inner = p.n_inner;
  check_constrained_reach(mesh, regions, sys.free, piece_starts);
  for (Vertex v : p.order)
    if (!positions[v].allFinite())
      throw InvalidInput("vertex " + std::to_string(v.idx()) + " has a non-finite position");

  const Csr lap = [&] {
    const FaceWeights fw = face_weights(mesh, positions, p, sys);
    level_weights(regions, settings, p, fw, sys);
    return laplacian_rows(mesh, p, fw);
  }();
  // Y_{m+1} = L Lam_m D Y_m for m = 1 .. k-1 (rows shrink ring by ring, the free rows last).
  for (int r = 0; r <= k; ++r) sys.ring_rows.push_back(row_count(p, r));
  auto apply_levels = [&](const Csr& first, Csr& out) -> const Csr& {
    const Csr* rows = &first;
    for (int m = 1; m <= k - 1; ++m) {
      const Eigen::VectorXd& w = sys.level_weights[static_cast<std::size_t>(m - 1)];
      out = scaled_product(lap, w, *rows, m == k - 1 ? n_free : row_count(p, k - 1 - m));
      rows = &out;
    }
    return *rows;
  };
  // S_k rows of the free vertices, from X_1 = L (k = 1: the (k-1)-ring is the free set, so lap
  // has exactly its rows).
  Csr x;
  const Csr* s_rows = &apply_levels(lap, x);
  const double sign = k % 2 == 1 ? -1.0 : 1.0;
  if (split_operator) {
    // outer = sign * (L Lam_{k-1} D) ... (L Lam_1 D): the same products started from the identity.
    Csr id;
    id.rows = id.cols = n_inner;
    for (int i = 0; i < n_inner; ++i) {
      id.inner.push_back(i);
      id.value.push_back(1.0);
      id.outer.push_back(i + 1);
    }
    Csr y;
    const Csr& product = apply_levels(id, y);
    Csr top = &product == &y ? std::move(y) : std::move(id);  // k = 1: the identity's first n_free rows
    top.rows = n_free;
    top.outer.resize(static_cast<std::size_t>(n_free) + 1);
    column_block(top, 0, n_inner, sign, false).swap(sys.outer);
  }
  // Swapped in, not assigned: Eigen 3.4's SparseMatrix has no move assignment, and assigning
  // the returned blocks copied them on one thread, with two copies of A_pp held at once.
  sys.lap = column_block(lap, 0, n_loc, 1.0, false);  // a conversion to rows: a copy either way
  column_block(*s_rows, 0, n_free, sign, false).swap(sys.a_pp);
  column_block(*s_rows, n_free, n_loc, sign, n_free > 0).swap(sys.a_pc);  // without the exact zeros of A_pc
  sys.constrained.assign(p.order.begin() + n_free, p.order.end());
  sys.symmetric = is_symmetric(sys.a_pp);
  return sys;
}

}  // namespace freeform
