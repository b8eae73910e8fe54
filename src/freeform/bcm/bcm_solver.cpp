// BcmSolver: one factorization, 3 + 4M solves, then per frame p = P_const + B G
// (docs/bcm.md).
#include "freeform/bcm/bcm_solver.h"

#include "freeform/bcm/bcm_system.h"
#include "freeform/bcm/boundary_band.h"
#include "freeform/bcm/refinement.h"

#include "freeform/common/cpu_features.h"
#include "freeform/common/error.h"
#include "freeform/common/parallel.h"
#include "freeform/mesh/bounds.h"
#include "freeform/numerics/sparse_solver.h"
#include "freeform/operators/face_geometry.h"
#include "freeform/param/anisotropic.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace freeform {
namespace {


// Rows below this are evaluated on one thread. Measured at 35k rows (bench_bcm, this 2-core VM):
// one thread 87 us, two 44 us idle; but with another process on one core the second thread
// gets preempted inside its chunk and the frame waits for it (p99 2-4 ms). One thread keeps
// the busy machine's 99th percentile near its median; from 64k rows on the halved time is
// worth that risk (parallel.h backs off after stalls).
constexpr int kParallelRows = 65536;

// p_i = c_i + sum_j B_ij G_j for rows [lo, hi); NH4 = 4M known at compile time when > 0. G is
// padded to 4 lanes (x, y, z, 0) per row j, so one row is n4 four-wide multiply-adds: a vector
// per FMA with AVX2, two with SSE2. Arguments __restrict: inside parallel_for's lambda
// (pointers captured by reference) the loop was not vectorized and took twice as long.
template <int NH4, class Store>
[[gnu::always_inline]] inline void rows_body(int lo, int hi, int n4_dynamic, const double* __restrict b,
                                             const double* __restrict c0, const double* __restrict g4,
                                             const Store& store) {
  const int n4 = NH4 > 0 ? NH4 : n4_dynamic;
  for (int i = lo; i < hi; ++i) {
    const double* bi = b + static_cast<std::ptrdiff_t>(i) * n4;
    double acc[4] = {c0[3 * i], c0[3 * i + 1], c0[3 * i + 2], 0.0};
    for (int j = 0; j < n4; ++j)
      for (int d = 0; d < 4; ++d) acc[d] += bi[j] * g4[4 * j + d];
    store(i, acc[0], acc[1], acc[2]);
  }
}

// The same body compiled for the build's baseline ISA and, on x86-64, for AVX2 + FMA, picked at
// run time: users' default builds get the wide vectors without -march=native.
template <int NH4, class Store>
void rows_baseline(int lo, int hi, int n4, const double* b, const double* c0, const double* g4, const Store& store) {
  rows_body<NH4>(lo, hi, n4, b, c0, g4, store);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <int NH4, class Store>
[[gnu::target("avx2,fma")]] void rows_avx2(int lo, int hi, int n4, const double* b, const double* c0, const double* g4,
                                            const Store& store) {
  rows_body<NH4>(lo, hi, n4, b, c0, g4, store);
}
const bool kHasAvx2 = cpu_has_avx2_fma();
#else
constexpr bool kHasAvx2 = false;
#endif

template <int NH4, class Store>
void kernel(int n, int n4_dynamic, const double* b, const double* c0, const double* g4, const Store& store) {
  parallel_for(n, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (kHasAvx2) {
      rows_avx2<NH4>(static_cast<int>(lo), static_cast<int>(hi), n4_dynamic, b, c0, g4, store);
      return;
    }
#endif
    rows_baseline<NH4>(static_cast<int>(lo), static_cast<int>(hi), n4_dynamic, b, c0, g4, store);
  });
}

// The operator's positions scaled by a power of two (exact) to an extent near 1: cotangents are
// unchanged, but areas of coordinates near 1e+-80 no longer overflow or underflow in the k-th
// power of the operator. The solution does not depend on the operator's scale.
VertexData<Vec3> unit_scaled(const VertexData<Vec3>& p) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& x : p.raw())
    if (x.allFinite()) {
      lo = std::min(lo, x.minCoeff());
      hi = std::max(hi, x.maxCoeff());
    }
  const double extent = hi - lo;  // max - min of all coordinates: no squares, no overflow below 1e308
  if (!(extent > 0.0) || !std::isfinite(extent)) return p;
  const int e = -std::ilogb(extent);  // ldexp, not a factor: 2^1030 for subnormal input overflows
  // Eigen's default constructor leaves the new array untouched: the pool takes its first touch.
  std::vector<Vec3> out(p.size());
  parallel_for(static_cast<std::ptrdiff_t>(p.size()), 65536, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto v = static_cast<std::size_t>(begin); v < static_cast<std::size_t>(end); ++v)
      for (int i = 0; i < 3; ++i) out[v][i] = std::ldexp(p.raw()[v][i], e);
  });
  return VertexData<Vec3>(std::move(out));
}

// A factorization or basis solve that failed without degenerate triangles, with the likely cause.
SolverError explain_ill_conditioned(const SolverError& e, const Mesh& mesh, const std::vector<Vertex>& free,
                                    int order) {
  const std::string needle = needle_cause(mesh, free, order);
  if (needle.empty())
    return SolverError(std::string(e.what()) +
                       "; the support's operator is singular: check the support for "
                       "coincident vertices and near-zero edges");
  return SolverError(std::string(e.what()) + "; " + needle);
}

// A failed factorization with the likely cause: degenerate triangles carry no stiffness, so the
// rows of vertices surrounded by them vanish. A_pp moves into the solver: the basis, the
// refinement and the nonlinear model need only A_pc and the unassembled operator.
SparseSolver factor_or_explain(const Mesh& mesh, const std::vector<Vertex>& free, BcmSystem& sys,
                               const BcmSettings& settings, CholeskyAnalysis* analysis) {
  try {
    return SparseSolver(std::move(sys.a_pp), sys.symmetric, settings.solver, analysis);
  } catch (const SolverError& e) {
    if (sys.degenerate_faces == 0) throw explain_ill_conditioned(e, mesh, free, settings.order);
    std::string faces;
    for (int f : sys.degenerate_examples) faces += (faces.empty() ? "" : ", ") + std::to_string(f);
    throw SolverError(std::string(e.what()) + "; " + std::to_string(sys.degenerate_faces) +
                      " triangle(s) in the support are degenerate (zero area or needle-thin; faces " + faces +
                      (sys.degenerate_faces > 5 ? ", ..." : "") +
                      ") and carry no stiffness: repair them (merge coincident vertices, remove slivers) or keep "
                      "them out of the support");
  }
}

// A bound on the position error at the rest transforms from per-column errors of [P_const B]:
// p = P_const + sum_m sum_q B_mq F0_mq.
double position_error(const Eigen::VectorXd& column_error, const std::vector<std::array<Vec3, 4>>& frames) {
  double e = column_error.head<3>().norm();
  for (std::size_t m = 0; m < frames.size(); ++m)
    for (std::size_t q = 0; q < 4; ++q) e += column_error[static_cast<Eigen::Index>(3 + 4 * m + q)] * frames[m][q].norm();
  return e;
}


// Anisotropic bending: the operator's cotangents and areas come from the equalized conformal
// map of the support grown by k rings (docs/anisotropic.md).
AnisotropicDomain support_domain(const Mesh& mesh, const Regions& regions, int order) {
  std::vector<Vertex> support;
  for (Vertex v : mesh.vertices())
    if (v.idx() < regions.n_vertices() && regions.role(v) != Role::Fixed) support.push_back(v);
  return anisotropic_domain(mesh, support, order);
}

}  // namespace

// The k-th power of a needle's cotangent and area ratios exceeds what double precision resolves
// (a CAD part's fans): its smallest corner below this is named as the likely cause.
constexpr double kNeedleDegrees = 1.0;

std::string needle_cause(const Mesh& mesh, const std::vector<Vertex>& free, int order) {
  double smallest = 180.0;
  int face = -1;
  for (Vertex v : free)
    for (Halfedge h : mesh.outgoing(v)) {
      const Face f = mesh.face(h);
      if (!f.is_valid()) continue;
      const detail::FaceCorners c = detail::face_corners(mesh, f);
      const detail::TriangleGeometry g =
          detail::triangle_geometry(mesh.position(c.v[0]), mesh.position(c.v[1]), mesh.position(c.v[2]));
      for (const double dot : g.dot) {
        const double angle = std::atan2(g.double_area, dot) * 180.0 / std::numbers::pi;
        if (angle < smallest) smallest = angle, face = f.idx();
      }
    }
  if (face < 0 || smallest >= kNeedleDegrees) return {};
  char angle[32];
  std::snprintf(angle, sizeof angle, "%.3g", smallest);
  return "the support's thinnest triangle (face " + std::to_string(face) + ", a corner of " + angle +
         " degrees) makes the order-" + std::to_string(order) +
         " system too ill-conditioned: use a lower order or keep needle triangles out of the support";
}

BcmSolver::BcmSolver(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                     const Progress& progress, const VertexData<Vec3>* operator_positions, bool keep_system,
                     RowOrder rows, BcmAnalysis* analysis)
    : n_vertices_(mesh.n_vertices()) {
  if (keep_system && rows != RowOrder::BreadthFirst)
    throw InvalidInput("BcmSolver: a kept system has breadth-first rows; RowOrder::ByIndex needs keep_system false");
  progress.step("assembly", 0.0);
  std::optional<BcmAnalysis> own_analysis;  // ordering the pattern on another thread meanwhile
  if (!analysis) analysis = &own_analysis.emplace(mesh, regions, settings);
  // Each phase's wall and CPU time (the report's "phases"); returns its wall time.
  const auto record = [this](const char* name, const PhaseClock& clock) {
    stats_.phases.push_back({name, clock.elapsed()});
    return stats_.phases.back().time.wall_ms;
  };
  AnisotropicDomain domain;
  if (settings.anisotropic) {
    const PhaseClock clock;
    domain = support_domain(mesh, regions, settings.order);
    stats_.anisotropic = domain.used;
    stats_.principal_extents = domain.extents;
    stats_.anisotropic_fallback = domain.fallback;
    stats_.parametrization_ms = domain.ms;
    record("parametrization", clock);
  }
  std::optional<PhaseClock> clock(std::in_place);
  BcmSystem sys = assemble_bcm_system(
      mesh, unit_scaled(domain.used ? domain.positions : operator_positions ? *operator_positions : mesh.positions()),
      regions, settings, keep_system);
  stats_.assembly_ms = record("assembly", *clock);
  stats_.symmetric = sys.symmetric;
  stats_.free = static_cast<int>(sys.free.size());
  stats_.constrained = static_cast<int>(sys.constrained.size());
  stats_.degenerate_faces = sys.degenerate_faces;
  stats_.clamped_cotangents = sys.clamped_cotangents;
  free_ = std::move(sys.free);
  progress.step("factorization", 0.15);

  clock.emplace();
  std::optional<SparseSolver> solver = factor_or_explain(mesh, free_, sys, settings, analysis->get());
  stats_.factorization_ms = record("factorization", *clock);
  stats_.analysis_ahead = solver->reused_analysis();
  stats_.analysis_ahead_ms = analysis->ms();
  stats_.analysis_ahead_cpu_ms = analysis->cpu_ms();
  stats_.solver = solver->name();
  stats_.ordering = solver->ordering();
  stats_.factor_nonzeros = solver->factor_nonzeros();
  progress.step("basis", 0.6);

  clock.emplace();
  const Eigen::MatrixXd xc = constrained_values(mesh, regions, sys.constrained, handle_frames(mesh, regions));
  Eigen::MatrixXd x;
  {
    const Eigen::MatrixXd rhs = -(sys.a_pc * xc);
    try {
      x = solver->solve(rhs, true, SolveKernel::Auto, &stats_.residual);  // one call, all 3 + 4M columns
    } catch (const SolverError& e) {
      throw explain_ill_conditioned(e, mesh, free_, settings.order);
    }
  }
  stats_.basis_ms = record("basis", *clock);
  progress.step("refinement", 0.75);
  clock.emplace();
  const Refinement refinement = refine_bcm_solution(sys, *solver, xc, x, progress);
  stats_.refinement_ms = record("refinement", *clock);
  if (!keep_system) solver.reset();  // the factor (2.6 GB at 1M free, k = 3) before the copies below
  stats_.refinement_steps = refinement.steps;
  stats_.refinement_converged = refinement.converged;
  const double diagonal = bounding_diagonal(mesh.positions());
  stats_.forward_error = position_error(refinement.correction, frames_) / diagonal;
  stats_.unrefined_error = position_error(refinement.initial, frames_) / diagonal;
  if (rows == RowOrder::ByIndex) sort_rows_by_vertex(x);
  const int n_mov = n_movable();
  constant_ = x.leftCols(3);
  basis_ = x.rightCols(4 * n_mov);
  if (n_mov > kStackHandles) scratch_.resize(static_cast<std::size_t>(16 * n_mov));
  if (keep_system) {
    // swap: Eigen 3.4's SparseMatrix has no move constructor, std::move would copy.
    const std::vector<double> c = smoothness_per_vertex(regions, settings);
    std::vector<double> smoothness(sys.constrained.size());
    for (std::size_t j = 0; j < smoothness.size(); ++j)
      smoothness[j] = c[static_cast<std::size_t>(sys.constrained[j].idx())];
    system_ = std::make_unique<BcmFactoredSystem>(BcmFactoredSystem{
        std::move(sys.constrained), {}, {}, {}, std::move(*solver), settings.order, std::move(smoothness)});
    system_->a_pc.swap(sys.a_pc);
    system_->lap.swap(sys.lap);
    system_->outer.swap(sys.outer);
  }
  progress.step("refinement", 0.9);
}

BcmRestSolution bcm_rest_solution(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                                  const Progress& progress) {
  if (settings.anisotropic) throw InvalidInput("bcm_rest_solution: anisotropic bending needs BcmSolver");
  progress.step("assembly", 0.0);
  BcmAnalysis analysis(mesh, regions, settings);
  BcmSystem sys = assemble_bcm_system(mesh, unit_scaled(mesh.positions()), regions, settings);
  progress.step("factorization", 0.15);
  const SparseSolver solver = factor_or_explain(mesh, sys.free, sys, settings, analysis.get());
  Eigen::MatrixXd xc(static_cast<Eigen::Index>(sys.constrained.size()), 3);
  for (Eigen::Index j = 0; j < xc.rows(); ++j)
    xc.row(j) = mesh.position(sys.constrained[static_cast<std::size_t>(j)]).transpose();
  Eigen::MatrixXd x = solver.solve(-(sys.a_pc * xc));
  progress.step("refinement", 0.75);
  refine_bcm_solution(sys, solver, xc, x, progress);
  BcmRestSolution out{std::move(sys.free), mesh.positions()};
  for (std::size_t i = 0; i < out.free.size(); ++i)
    out.positions[out.free[i]] = x.row(static_cast<Eigen::Index>(i)).transpose();
  return out;
}

std::vector<double> BcmSolver::handle_frames(const Mesh& mesh, const Regions& regions) {
  // Virtual frame per movable handle: centroid c and c + s e_i, s = extent (> 0).
  const int n_mov = regions.n_movable();
  frames_.resize(static_cast<std::size_t>(n_mov));
  centroids_.resize(static_cast<std::size_t>(n_mov));
  std::vector<double> extent(static_cast<std::size_t>(n_mov), 1.0);
  for (std::size_t h = 0; h < regions.handles().size(); ++h) {
    const int m = regions.movable_index(static_cast<int>(h));
    if (m < 0) continue;
    const auto& vs = regions.handles()[h].vertices;
    Vec3 c = Vec3::Zero();
    for (Vertex v : vs) c += mesh.position(v);
    c /= static_cast<double>(vs.size());
    double s = 0.0;
    for (Vertex v : vs) s = std::max(s, (mesh.position(v) - c).norm());
    if (!(s > 0.0)) {  // a single vertex (or coincident ones): mean edge length around it
      double sum = 0.0;
      int cnt = 0;
      for (Halfedge he : mesh.outgoing(vs.front())) {
        sum += (mesh.position(mesh.to_vertex(he)) - mesh.position(vs.front())).norm();
        ++cnt;
      }
      s = cnt > 0 && sum > 0.0 ? sum / cnt : 1.0;
    }
    const auto mi = static_cast<std::size_t>(m);
    centroids_[mi] = c;
    extent[mi] = s;
    frames_[mi] = {c, c + s * Vec3::UnitX(), c + s * Vec3::UnitY(), c + s * Vec3::UnitZ()};
    for (Vertex v : vs) {
      handle_vertices_.push_back(v);
      handle_owner_.push_back(m);
      handle_rest_.push_back(mesh.position(v));
    }
  }
  return extent;
}

Eigen::MatrixXd BcmSolver::constrained_values(const Mesh& mesh, const Regions& regions,
                                              const std::vector<Vertex>& constrained,
                                              const std::vector<double>& extent) const {
  // Rest positions (fixed, immovable handles) in columns 0-2, and Q_m (affine coordinates in
  // the frame, rows sum to 1) in columns 3 + 4m .. 3 + 4m + 3.
  const int n_c = static_cast<int>(constrained.size());
  Eigen::MatrixXd xc = Eigen::MatrixXd::Zero(n_c, 3 + 4 * n_movable());
  for (int j = 0; j < n_c; ++j) {
    const Vertex v = constrained[static_cast<std::size_t>(j)];
    const int h = regions.handle_of(v);
    const int m = h >= 0 ? regions.movable_index(h) : -1;
    if (m < 0) {
      xc.row(j).head<3>() = mesh.position(v).transpose();
    } else {
      const auto mi = static_cast<std::size_t>(m);
      const Vec3 a = (mesh.position(v) - centroids_[mi]) / extent[mi];
      xc(j, 3 + 4 * m) = 1.0 - a.sum();
      xc.row(j).segment<3>(3 + 4 * m + 1) = a.transpose();
    }
  }
  return xc;
}

void BcmSolver::sort_rows_by_vertex(Eigen::MatrixXd& x) {
  std::vector<int> order(free_.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return free_[static_cast<std::size_t>(a)] < free_[static_cast<std::size_t>(b)]; });
  const Eigen::Map<const Eigen::VectorXi> perm(order.data(), static_cast<Eigen::Index>(order.size()));
  x = Eigen::MatrixXd(x(perm, Eigen::all));
  std::vector<Vertex> sorted(free_.size());
  for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = free_[static_cast<std::size_t>(order[i])];
  free_ = std::move(sorted);
}

int BcmSolver::n_free() const { return static_cast<int>(free_.size()); }
int BcmSolver::n_movable() const { return static_cast<int>(frames_.size()); }
const std::vector<Vertex>& BcmSolver::free_vertices() const { return free_; }

Vec3 BcmSolver::handle_centroid(int movable) const {
  if (movable < 0 || movable >= n_movable())
    throw InvalidInput("movable handle index " + std::to_string(movable) + " is out of range (" +
                       std::to_string(n_movable()) + " movable handles)");
  return centroids_[static_cast<std::size_t>(movable)];
}

const double* BcmSolver::frame_matrix(std::span<const Eigen::Affine3d> transforms, double* stack_buffer) const {
  const int n_mov = n_movable();
  if (static_cast<int>(transforms.size()) != n_mov)
    throw InvalidInput("evaluate: got " + std::to_string(transforms.size()) + " transforms for " +
                       std::to_string(n_mov) + " movable handles");
  double* g = n_mov <= kStackHandles ? stack_buffer : scratch_.data();
  for (int m = 0; m < n_mov; ++m) {
    const Eigen::Affine3d& tm = transforms[static_cast<std::size_t>(m)];
    if (!tm.matrix().allFinite()) throw InvalidInput("evaluate: transform " + std::to_string(m) + " is not finite");
    for (int j = 0; j < 4; ++j) {
      const Vec3 y = tm * frames_[static_cast<std::size_t>(m)][static_cast<std::size_t>(j)];
      for (int d = 0; d < 3; ++d) g[16 * m + 4 * j + d] = y[d];
      g[16 * m + 4 * j + 3] = 0.0;
    }
  }
  return g;
}

template <class Store>
void BcmSolver::run(const double* g, const Store& store) const {
  const int n = n_free();
  const int n4 = 4 * n_movable();
  const double* b = basis_.data();
  const double* c0 = constant_.data();
  switch (n4) {
    case 0: kernel<0>(n, 0, b, c0, g, store); break;
    case 4: kernel<4>(n, 4, b, c0, g, store); break;
    case 8: kernel<8>(n, 8, b, c0, g, store); break;
    case 12: kernel<12>(n, 12, b, c0, g, store); break;
    default: kernel<0>(n, n4, b, c0, g, store); break;
  }
}

void BcmSolver::evaluate(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<RowMatrixX3d> out) const {
  if (out.rows() != n_free())
    throw InvalidInput("evaluate: output has " + std::to_string(out.rows()) + " rows, expected " +
                       std::to_string(n_free()) + " (one per free vertex)");
  double buffer[16 * kStackHandles];
  const double* g = frame_matrix(transforms, buffer);
  double* o = out.data();
  const Eigen::Index stride = out.outerStride();
  run(g, [o, stride](int i, double x, double y, double z) {
    double* r = o + i * stride;
    r[0] = x;
    r[1] = y;
    r[2] = z;
  });
}

void BcmSolver::evaluate(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("evaluate: positions have " + std::to_string(positions.size()) + " entries, the mesh has " +
                       std::to_string(n_vertices_) + " vertices");
  double buffer[16 * kStackHandles];
  const double* g = frame_matrix(transforms, buffer);
  Vec3* pos = positions.raw().data();
  const Vertex* fv = free_.data();
  run(g, [pos, fv](int i, double x, double y, double z) { pos[fv[i].idx()] = Vec3(x, y, z); });
  move_handles(transforms, positions);
}

void BcmSolver::move_handles(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions) const {
  for (std::size_t i = 0; i < handle_vertices_.size(); ++i)
    positions[handle_vertices_[i]] = transforms[static_cast<std::size_t>(handle_owner_[i])] * handle_rest_[i];
}

}  // namespace freeform
