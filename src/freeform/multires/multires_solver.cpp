// MultiresSolver: decomposition (base + per-vertex encoding) once, reconstruction per frame
// (docs/multires.md).
#include "freeform/multires/multires_solver.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"
#include "freeform/mesh/traversal.h"
#include "freeform/multires/normal_displacement.h"
#include "freeform/multires/operator_shape.h"
#include "freeform/multires/vertex_frame.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <span>
#include <string>

namespace freeform {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Loops shorter than this run on one thread (thread start-up costs more than the work).
constexpr int kParallelRows = 4096;
// Steps of the descent to the base vertex nearest to a detail point.
constexpr int kMaxDescent = 64;
// Detail is flattened where det of its offset map falls below this fraction of its rest value.
constexpr double kFlattenFraction = 0.05;
// A detail triangle is checked for flips if |cos(detail normal, base normal)| > this at rest.
constexpr double kFacingCosine = 0.2;

using Map3 = Eigen::Map<const Vec3>;

const MultiresOptions& validated(const MultiresOptions& o) {
  if (o.search_rings < 1 || o.search_rings > 8)
    throw InvalidInput("multiresolution: search_rings must be in [1, 8], got " + std::to_string(o.search_rings));
  if (!(o.barycentric_tolerance >= 0.0 && o.barycentric_tolerance < 0.5))
    throw InvalidInput("multiresolution: barycentric_tolerance must be in [0, 0.5)");
  if (o.encoding == MultiresOptions::Encoding::VertexFrame && o.model)
    throw InvalidInput("multiresolution: vertex frames ride on the linear base only (the nonlinear base uses normal displacement)");
  return o;
}

// Automatic: vertex frames over the paper's base where the detail stands on its base (the
// smooth foot-point shape exists: no overhang, not a tube, not anisotropic), normal displacement
// elsewhere (docs/multires.md, "Which encoding"). The nonlinear base always uses normal
// displacement over the smooth shape where it exists.
MultiresOptions::Encoding resolved(const MultiresOptions& o, const OperatorShape& shape) {
  if (o.encoding != MultiresOptions::Encoding::Automatic) return o.encoding;
  if (o.model) return MultiresOptions::Encoding::Normal;
  return shape.positions.size() > 0 ? MultiresOptions::Encoding::VertexFrame : MultiresOptions::Encoding::Normal;
}

// The smooth shape: the base's operator for normal displacement, and what decides Automatic.
OperatorShape wanted_shape(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                           const MultiresOptions& options, const Progress& progress) {
  if (options.encoding == MultiresOptions::Encoding::VertexFrame) return {};
  return base_operator_shape(mesh, regions, settings, progress);
}

}  // namespace

// The search walks local indices (compact, free vertices first in breadth-first order) instead
// of the mesh's: at 1M free most of its time was cache misses on #V-sized arrays. Per local
// vertex within rings + 1 rings of the free set, in mesh.outgoing order: the neighbour and the
// face before it (-1 on a boundary).
struct MultiresSolver::LocalAdjacency {
  struct Step {
    int to, face;
  };
  std::vector<int> offset;
  std::vector<Step> steps;
  std::vector<char> near;  // within one ring of the free set

  LocalAdjacency(const Mesh& mesh, const std::vector<int>& local_global, const VertexData<int>& dist,
                 const VertexData<int>& local, const FaceData<int>& local_face, int rings)
      : offset(local_global.size() + 1, 0), near(local_global.size(), 0) {
    for (std::size_t l = 0; l < local_global.size(); ++l) {
      const Vertex v(local_global[l]);
      near[l] = dist[v] >= 0 && dist[v] <= 1;  // handle vertices may be far (-1)
      if (dist[v] >= 0 && dist[v] <= rings + 1)
        for (Halfedge he : mesh.outgoing(v)) {
          const Face f = mesh.face(he);
          steps.push_back({local[mesh.to_vertex(he)], f.is_valid() ? local_face[f] : -1});
        }
      offset[l + 1] = static_cast<int>(steps.size());
    }
  }
  std::span<const Step> around(int l) const {
    return {steps.data() + offset[static_cast<std::size_t>(l)], steps.data() + offset[static_cast<std::size_t>(l) + 1]};
  }
};

// Per thread: the search's fronts and candidates, and the marks of the free vertex that saw a
// local vertex / face last (instead of linear searches over the candidates: 0.5-0.9 s of the
// encoding's 8 s at 1M free).
struct MultiresSolver::EncodeScratch {
  std::vector<int> frontier, next, cand, vertex_seen, face_seen;
};

MultiresSolver::MultiresSolver(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                               const MultiresOptions& options, const Progress& progress)
    : MultiresSolver(mesh, regions, settings, options, progress, wanted_shape(mesh, regions, settings, options, progress)) {}

MultiresSolver::MultiresSolver(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                               const MultiresOptions& options, const Progress& progress, const OperatorShape& shape,
                               BcmAnalysis* analysis)
    : bcm_(mesh, regions, settings, progress,
           resolved(validated(options), shape) != MultiresOptions::Encoding::VertexFrame && shape.positions.size() > 0
               ? &shape.positions
               : nullptr,
           static_cast<bool>(options.model), RowOrder::BreadthFirst, analysis),
      n_vertices_(mesh.n_vertices()),
      vertex_frames_(resolved(options, shape) == MultiresOptions::Encoding::VertexFrame) {
  stats_.smooth_operator = shape.positions.size() > 0 && !vertex_frames_;
  stats_.operator_fallback = shape.fallback;
  stats_.operator_shape_ms = shape.ms;
  progress.step("detail", 0.9);
  const auto t0 = Clock::now();
  const std::vector<Vertex>& free = bcm_.free_vertices();
  n_free_ = static_cast<int>(free.size());
  // The candidate search starts at the base vertex nearest to x_i, found by a descent that stays
  // within one ring of the free vertices; candidate faces lie within `rings` rings of it. So
  // normals are recomputed within rings + 1 rings of the free vertices (this includes the
  // support's first ring), and positions are needed one ring further.
  const int normal_rings = options.search_rings + 1;
  const VertexData<int> dist = ring_distance(mesh, free, normal_rings + 1);
  VertexData<int> local(static_cast<std::size_t>(n_vertices_), -1);
  FaceData<int> local_face(static_cast<std::size_t>(mesh.n_faces()), -1);
  build_local(mesh, regions, dist, normal_rings, local, local_face);
  const int n_local = static_cast<int>(local_global_.size());
  {
    std::vector<char> wanted(static_cast<std::size_t>(n_local), 0);
    for (int l = 0; l < n_local; ++l) {
      const int d = dist[Vertex(local_global_[static_cast<std::size_t>(l)])];
      wanted[static_cast<std::size_t>(l)] = d >= 0 && d <= normal_rings;
    }
    select_normal_vertices(mesh, local_face, wanted);
  }

  // --- rest base (identity manipulators) and its normals, with the per-frame code ---
  base_.resize(n_local, 3);
  for (int l = n_moving_; l < n_local; ++l)
    base_.row(l) = mesh.position(Vertex(local_global_[static_cast<std::size_t>(l)])).transpose();
  normal_.setZero(n_local, 3);
  const std::vector<Eigen::Affine3d> identity(static_cast<std::size_t>(bcm_.n_movable()), Eigen::Affine3d::Identity());
  update_base(identity, Base::Linear);
  update_normals();

  // --- encode every free vertex ---
  codes_.resize(static_cast<std::size_t>(n_free_));
  min_ratio_.assign(static_cast<std::size_t>(n_free_), -std::numeric_limits<double>::infinity());
  rest_sign_.assign(static_cast<std::size_t>(n_free_), 0);
  if (vertex_frames_) {
    encode_vertex_frames(mesh, local, local_face);
  } else {
    encode_displaced(mesh, LocalAdjacency(mesh, local_global_, dist, local, local_face, options.search_rings),
                     resolved(options, shape) == MultiresOptions::Encoding::Normal, options, progress);
  }
  progress.check();
  count_codes();
  if (!vertex_frames_) {  // per frame, normals are needed at the corners of the encodings only
    std::vector<char> used(static_cast<std::size_t>(n_local), 0);
    for (const Code& c : codes_) {
      used[static_cast<std::size_t>(c.corner[0])] = 1;
      if (c.corner[2] >= 0) used[static_cast<std::size_t>(c.corner[1])] = used[static_cast<std::size_t>(c.corner[2])] = 1;
    }
    select_normal_vertices(mesh, local_face, used);
  }
  set_detail_rest_signs(mesh);
  if (options.model) {  // the iterating base keeps the smooth rest base
    VertexData<Vec3> rest_base = mesh.positions();
    for (int i = 0; i < n_free_; ++i) rest_base[free[static_cast<std::size_t>(i)]] = base_.row(i).transpose();
    model_ = options.model(mesh, regions, bcm_, rest_base);
  }
  stats_.decomposition_ms = ms_since(t0) + shape.ms;
  progress.step("detail", 1.0);
}

// Local vertices: free (BCM order), movable handle vertices, then the constant ones within
// normal_rings + 1 rings; local faces: every face with a corner whose normal is recomputed.
void MultiresSolver::build_local(const Mesh& mesh, const Regions& regions, const VertexData<int>& dist,
                                 int normal_rings, VertexData<int>& local, FaceData<int>& local_face) {
  auto add_local = [&](Vertex v) {
    if (local[v] >= 0) return;
    local[v] = static_cast<int>(local_global_.size());
    local_global_.push_back(v.idx());
  };
  for (Vertex v : bcm_.free_vertices()) add_local(v);
  for (std::size_t h = 0; h < regions.handles().size(); ++h) {
    const int m = regions.movable_index(static_cast<int>(h));
    if (m < 0) continue;
    for (Vertex v : regions.handles()[h].vertices) {
      add_local(v);
      handle_owner_.push_back(m);
      handle_rest_.push_back(mesh.position(v));
    }
  }
  n_moving_ = static_cast<int>(local_global_.size());
  for (Vertex v : mesh.vertices())
    if (dist[v] >= 0) add_local(v);
  const int n_local = static_cast<int>(local_global_.size());
  for (int l = 0; l < n_local; ++l)
    for (Halfedge around : mesh.outgoing(Vertex(local_global_[static_cast<std::size_t>(l)]))) {
      const Face f = mesh.face(around);
      if (!f.is_valid() || local_face[f] >= 0) continue;
      const auto vs = mesh.vertices(f);
      if (std::none_of(vs.begin(), vs.end(), [&](Vertex v) { return dist[v] >= 0 && dist[v] <= normal_rings; }))
        continue;
      local_face[f] = static_cast<int>(faces_.size());
      faces_.push_back({local[vs[0]], local[vs[1]], local[vs[2]]});
      if (std::any_of(vs.begin(), vs.end(), [&](Vertex v) { return regions.role(v) == Role::Free; })) {
        detail_faces_.push_back(local_face[f]);
        for (Vertex v : vs) detail_face_global_.push_back(v.idx());
      }
    }
}

// Per frame: face normals of normal_faces_, then each normal vertex sums those around it.
void MultiresSolver::select_normal_vertices(const Mesh& mesh, const FaceData<int>& local_face,
                                            const std::vector<char>& wanted) {
  normal_vertices_.clear();
  normal_faces_.clear();
  vf_faces_.clear();
  vf_offset_.assign(1, 0);
  std::vector<int> slot(faces_.size(), -1);  // local face -> its row among normal_faces_
  for (std::size_t l = 0; l < wanted.size(); ++l) {
    if (!wanted[l]) continue;
    normal_vertices_.push_back(static_cast<int>(l));
    for (Halfedge he : mesh.outgoing(Vertex(local_global_[l]))) {
      const Face f = mesh.face(he);
      if (!f.is_valid()) continue;
      int& r = slot[static_cast<std::size_t>(local_face[f])];
      if (r < 0) {
        r = static_cast<int>(normal_faces_.size());
        normal_faces_.push_back(local_face[f]);
      }
      vf_faces_.push_back(r);
    }
    vf_offset_.push_back(static_cast<int>(vf_faces_.size()));
  }
  fnormal_.resize(static_cast<Eigen::Index>(normal_faces_.size()), 3);
}

void MultiresSolver::encode_displaced(const Mesh& mesh, const LocalAdjacency& adjacency, bool normal_encoding,
                                      const MultiresOptions& options, const Progress& progress) {
  const std::vector<Vertex>& free = bcm_.free_vertices();
  const std::atomic<bool>* cancel = progress.cancel;
#pragma omp parallel num_threads(thread_budget())
  {
    EncodeScratch scratch;
    if (normal_encoding) {
      scratch.vertex_seen.assign(local_global_.size(), -1);
      scratch.face_seen.assign(faces_.size(), -1);
    }
#pragma omp for schedule(dynamic, 256)
    for (int i = 0; i < n_free_; ++i) {
      if (cancel && cancel->load(std::memory_order_relaxed)) continue;  // 5 s at 1M free: stop early
      const Vec3 x = mesh.position(free[static_cast<std::size_t>(i)]);
      codes_[static_cast<std::size_t>(i)].corner = {-1, -1, -1};
      const int start = nearest_base_vertex(i, x, adjacency);
      if (!normal_encoding || !encode_on_faces(i, x, start, adjacency, options, scratch))
        encode_in_frame(i, x, start, adjacency);
    }
  }
}

// Descent to the nearest base vertex (local minimum of |b - x|) within one ring of the free set;
// free vertex i is local vertex i.
int MultiresSolver::nearest_base_vertex(int i, const Vec3& x, const LocalAdjacency& adjacency) const {
  const double* B = base_.data();
  int start = i;
  double dmin = (Map3(B + 3 * i) - x).squaredNorm();
  for (int step = 0; step < kMaxDescent; ++step) {
    int next_v = start;
    for (const LocalAdjacency::Step& e : adjacency.around(start)) {
      if (!adjacency.near[static_cast<std::size_t>(e.to)]) continue;
      const double d = (Map3(B + 3 * e.to) - x).squaredNorm();
      if (d < dmin) {
        dmin = d;
        next_v = e.to;
      }
    }
    if (next_v == start) break;
    start = next_v;
  }
  return start;
}

// Normal displacement over the base triangles within `rings` rings of `start`: the fit of least
// |height|. False if none fits.
bool MultiresSolver::encode_on_faces(int i, const Vec3& x, int start, const LocalAdjacency& adjacency,
                                     const MultiresOptions& options, EncodeScratch& scratch) {
  using Step = LocalAdjacency::Step;
  const auto around = [&](int l) { return adjacency.around(l); };
  const double* B = base_.data();
  const double* N = normal_.data();
  const double tol = options.barycentric_tolerance;
  const int rings = options.search_rings;
  std::vector<int>& frontier = scratch.frontier;
  std::vector<int>& next = scratch.next;
  std::vector<int>& cand = scratch.cand;
  std::vector<int>& vertex_seen = scratch.vertex_seen;
  std::vector<int>& face_seen = scratch.face_seen;
  Code& code = codes_[static_cast<std::size_t>(i)];
  bool found = false;
  multires::NormalFit best;
  vertex_seen[static_cast<std::size_t>(start)] = i;
  frontier.assign(1, start);
  cand.clear();
  for (int level = 1; level <= rings && !(found && level > 2); ++level) {
    // Faces around the vertices at ring distance level - 1 (new ones only).
    const std::size_t first_new = cand.size();
    next.clear();
    for (int g : frontier)
      for (const Step& e : around(g)) {
        if (e.face >= 0 && face_seen[static_cast<std::size_t>(e.face)] != i) {
          face_seen[static_cast<std::size_t>(e.face)] = i;
          cand.push_back(e.face);
        }
        if (vertex_seen[static_cast<std::size_t>(e.to)] != i) {
          vertex_seen[static_cast<std::size_t>(e.to)] = i;
          next.push_back(e.to);
        }
      }
    frontier.swap(next);
    for (std::size_t k = first_new; k < cand.size(); ++k) {
      const auto& fc = faces_[static_cast<std::size_t>(cand[k])];
      if (best.ok && multires::fit_height_lower_bound(x, Map3(B + 3 * fc[0]), Map3(B + 3 * fc[1]),
                                                      Map3(B + 3 * fc[2]), tol) >= std::abs(best.h))
        continue;  // cannot win: same choice, without its cubic
      const multires::NormalFit fit = multires::fit_normal_displacement(
          x, Map3(B + 3 * fc[0]), Map3(B + 3 * fc[1]), Map3(B + 3 * fc[2]), Map3(N + 3 * fc[0]),
          Map3(N + 3 * fc[1]), Map3(N + 3 * fc[2]), tol);
      if (fit.ok && (!best.ok || std::abs(fit.h) < std::abs(best.h))) {
        best = fit;
        code.corner = fc;
      }
    }
    found = best.ok;
  }
  if (found) {
    code.w = {best.u, best.v, best.w};
    code.h = best.h;
    const std::int8_t rest_sign = best.det > 0 ? 1 : (best.det < 0 ? -1 : 0);
    rest_sign_[static_cast<std::size_t>(i)] = rest_sign;
    const auto& fc = code.corner;
    const multires::JacobianRay ray = multires::offset_jacobian_ray(
        Map3(B + 3 * fc[0]), Map3(B + 3 * fc[1]), Map3(B + 3 * fc[2]), Map3(N + 3 * fc[0]), Map3(N + 3 * fc[1]),
        Map3(N + 3 * fc[2]), best.u, best.v, best.w);
    if (rest_sign > 0 && ray.a0 > 0.0) {
      const double min_ratio = kFlattenFraction * ray.at(best.h) / ray.a0;
      min_ratio_[static_cast<std::size_t>(i)] = min_ratio;
      code.min_det = min_ratio * ray.a0;  // -inf (never) unless set here
    }
  }
  return found;
}

// Local frame at the nearest base vertex (no base triangle fits).
void MultiresSolver::encode_in_frame(int i, const Vec3& x, int start, const LocalAdjacency& adjacency) {
  using Step = LocalAdjacency::Step;
  const auto around = [&](int l) { return adjacency.around(l); };
  const double* B = base_.data();
  const double* N = normal_.data();
  Code& code = codes_[static_cast<std::size_t>(i)];
  const Vec3 pa = Map3(B + 3 * start), n = Map3(N + 3 * start);
  int nbr = -1;
  double best_len = 0.0;
  for (const Step& out : around(start)) {
    const int l = out.to;
    Vec3 e = Map3(B + 3 * l) - pa;
    const double len = (e - e.dot(n) * n).norm();
    if (len > best_len * (1.0 + 1e-12)) {
      best_len = len;
      nbr = l;
    }
  }
  const Vec3 d = x - pa;
  code.corner = {start, -1, -1};
  code.w = {d[0], d[1], d[2]};
  code.h = 0.0;
  if (nbr >= 0 && n.squaredNorm() > 0.5) {
    Vec3 e = Map3(B + 3 * nbr) - pa;
    e = (e - e.dot(n) * n).normalized();
    const Vec3 b = n.cross(e);
    code.corner[1] = nbr;
    code.w = {d.dot(e), d.dot(b), d.dot(n)};
  }
}

void MultiresSolver::count_codes() {
  for (std::size_t i = 0; i < codes_.size(); ++i) {
    const Code& c = codes_[i];
    if (vertex_frames_) {
      ++stats_.vertex_frames;
      if (c.corner[1] >= 0) stats_.max_height = std::max(stats_.max_height, std::abs(c.w[2]));
    } else if (c.corner[2] >= 0) {
      ++stats_.normal_encoded;
      stats_.max_height = std::max(stats_.max_height, std::abs(c.h));
      if (rest_sign_[i] <= 0) ++stats_.rest_folded;
    } else {
      ++stats_.fallback;
    }
  }
  stats_.free = n_free_;
}

// Rest orientation of the detail triangles against their base triangles.
void MultiresSolver::set_detail_rest_signs(const Mesh& mesh) {
  detail_rest_sign_.resize(detail_faces_.size());
  const auto sign = [&](std::size_t k) {
    const Vec3 p0 = mesh.position(Vertex(detail_face_global_[3 * k]));
    const Vec3 p1 = mesh.position(Vertex(detail_face_global_[3 * k + 1]));
    const Vec3 p2 = mesh.position(Vertex(detail_face_global_[3 * k + 2]));
    // Only triangles clearly facing along (or against) the base are checked: a detail triangle
    // nearly perpendicular to its base triangle (walls of sharp features) has no meaningful side.
    const Vec3 dn = (p1 - p0).cross(p2 - p0), bn = base_face_normal(detail_faces_[k]);
    const double c = dn.dot(bn), scale = dn.norm() * bn.norm();
    return c > kFacingCosine * scale ? 1 : (c < -kFacingCosine * scale ? -1 : 0);
  };
  parallel_for(static_cast<std::ptrdiff_t>(detail_faces_.size()), kParallelRows,
               [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                 for (auto k = static_cast<std::size_t>(lo); k < static_cast<std::size_t>(hi); ++k)
                   detail_rest_sign_[k] = sign(k);
               });
}

std::vector<bool> MultiresSolver::fallback_mask() const {
  std::vector<bool> out(codes_.size());
  for (std::size_t i = 0; i < codes_.size(); ++i) out[i] = !vertex_frames_ && codes_[i].corner[2] < 0;
  return out;
}

void MultiresSolver::encode_vertex_frames(const Mesh& mesh, const VertexData<int>& local,
                                          const FaceData<int>& local_face) {
  // Per free vertex: its ring (local vertices) for the tangent; normals at the free vertices.
  ring_offset_.assign(1, 0);
  ring_.clear();
  for (int i = 0; i < n_free_; ++i) {
    for (Halfedge he : mesh.outgoing(Vertex(local_global_[static_cast<std::size_t>(i)])))
      ring_.push_back(local[mesh.to_vertex(he)]);
    ring_offset_.push_back(static_cast<int>(ring_.size()));
  }
  std::vector<char> free_only(local_global_.size(), 0);
  std::fill(free_only.begin(), free_only.begin() + n_free_, 1);
  select_normal_vertices(mesh, local_face, free_only);
  update_normals();  // the per-frame normals, here at rest
  ring_weight_.resize(2 * ring_.size());
  tangent_.resize(n_free_, 3);
  const double* B = base_.data();
  const double* N = normal_.data();
  const multires::RingStencil stencil = ring_stencil();
  parallel_for(n_free_, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<int>(lo); i < static_cast<int>(hi); ++i) {
      const int first = ring_offset_[static_cast<std::size_t>(i)];
      const int count = ring_offset_[static_cast<std::size_t>(i) + 1] - first;
      const Vec3 center = Map3(B + 3 * i), n = Map3(N + 3 * i);
      multires::stencil_weights(center, n, count,
                                [&](int j) { return Vec3(Map3(B + 3 * ring_[static_cast<std::size_t>(first + j)])); },
                                ring_weight_.data() + 2 * first);
    }
    // The rest tangents by the per-frame kernel itself: the identity edit reproduces the input.
    multires::ring_tangents(stencil, B, static_cast<int>(base_.rows()), N, static_cast<int>(lo), static_cast<int>(hi),
                            tangent_.data());
    for (auto i = static_cast<int>(lo); i < static_cast<int>(hi); ++i) {
      const Vec3 center = Map3(B + 3 * i), n = Map3(N + 3 * i);
      const Vec3 t = multires::normalized_or_zero(tangent_.row(i).transpose());
      const Vec3 d = mesh.position(Vertex(local_global_[static_cast<std::size_t>(i)])) - center;
      Code& code = codes_[static_cast<std::size_t>(i)];
      const bool framed = n.squaredNorm() > 0.5 && t.squaredNorm() > 0.5;
      code.corner = {i, framed ? 0 : -1, -1};  // corner[1] = -1: a pure offset (no frame)
      code.w = framed ? std::array<double, 3>{d.dot(t), d.dot(n.cross(t)), d.dot(n)} : std::array<double, 3>{d[0], d[1], d[2]};
    }
  });
  // The per-frame loop reads the frame coordinates packed; the few vertices without a frame are
  // placed by their offset after it.
  frame_w_.assign(3 * static_cast<std::size_t>(n_free_), 0.0);
  unframed_.clear();
  for (int i = 0; i < n_free_; ++i) {
    const Code& c = codes_[static_cast<std::size_t>(i)];
    if (c.corner[1] < 0)
      unframed_.push_back(i);
    else
      std::copy(c.w.begin(), c.w.end(), frame_w_.begin() + 3 * i);
  }
}

multires::RingStencil MultiresSolver::ring_stencil() const {
  return {ring_offset_.data(), ring_.data(), ring_weight_.data()};
}

void MultiresSolver::update_base(std::span<const Eigen::Affine3d> transforms, Base source,
                                 const Eigen::Ref<const RowMatrixX3d>* given, const Progress& progress) const {
  auto top = base_.topRows(n_free_);
  if (source == Base::Linear || !model_) {
    bcm_.evaluate(transforms, top);  // checks the count and finiteness of the transforms
  } else if (source == Base::ModelSolve) {
    model_->solve(transforms, top, progress);  // checks them too
  } else {
    if (static_cast<int>(transforms.size()) != bcm_.n_movable())
      throw InvalidInput("reconstruct: got " + std::to_string(transforms.size()) + " transforms for " +
                         std::to_string(bcm_.n_movable()) + " movable handles");
    if (given->rows() != n_free_)
      throw InvalidInput("reconstruct: the base has " + std::to_string(given->rows()) + " rows for " +
                         std::to_string(n_free_) + " free vertices");
    top = *given;
  }
  const int n_handle = n_moving_ - n_free_;
  double* b = base_.data();
  parallel_for(n_handle, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto k = static_cast<std::size_t>(lo); k < static_cast<std::size_t>(hi); ++k) {
      const Vec3 y = transforms[static_cast<std::size_t>(handle_owner_[k])] * handle_rest_[k];
      double* r = b + 3 * (static_cast<std::ptrdiff_t>(n_free_) + static_cast<std::ptrdiff_t>(k));
      r[0] = y[0];
      r[1] = y[1];
      r[2] = y[2];
    }
  });
}

Vec3 MultiresSolver::base_face_normal(int f) const {
  const auto& c = faces_[static_cast<std::size_t>(f)];
  const Vec3 p0 = base_.row(c[0]).transpose();
  return (base_.row(c[1]).transpose() - p0).cross(base_.row(c[2]).transpose() - p0);  // area weighted
}

void MultiresSolver::update_normals() const {
  const double* b = base_.data();
  double* fn = fnormal_.data();
  const int nf = static_cast<int>(normal_faces_.size());
  const int* fs = normal_faces_.data();
  const std::array<int, 3>* faces = faces_.data();
  parallel_for(nf, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto k = static_cast<int>(lo); k < static_cast<int>(hi); ++k) {
      const std::array<int, 3>& f = faces[fs[k]];
      const Vec3 p0 = Map3(b + 3 * f[0]);
      const Vec3 n = (Map3(b + 3 * f[1]) - p0).cross(Map3(b + 3 * f[2]) - p0);  // area weighted
      fn[3 * k] = n[0];
      fn[3 * k + 1] = n[1];
      fn[3 * k + 2] = n[2];
    }
  });
  double* vn = normal_.data();
  const int nv = static_cast<int>(normal_vertices_.size());
  const int* off = vf_offset_.data();
  const int* vf = vf_faces_.data();
  const int* nvs = normal_vertices_.data();
  parallel_for(nv, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto k = static_cast<int>(lo); k < static_cast<int>(hi); ++k) {
      Vec3 n = Vec3::Zero();
      for (int j = off[k]; j < off[k + 1]; ++j) n += Map3(fn + 3 * vf[j]);
      const double sq = n.squaredNorm();
      if (sq > 0.0) n *= 1.0 / std::sqrt(sq);
      double* r = vn + 3 * nvs[k];
      r[0] = n[0];
      r[1] = n[1];
      r[2] = n[2];
    }
  });
}

// Out of line: rare, and keeping it out of the reconstruction loop keeps that loop fast.
// Out of line and reloading its inputs by index: rare, and nothing of the reconstruction loop
// has to live in memory across this call (passing the loop's vectors by reference cost 25 %).
[[gnu::noinline]] int MultiresSolver::flatten_detail(int i, Vec3* out) const {
  const Code& c = codes_[static_cast<std::size_t>(i)];
  const double min_ratio = min_ratio_[static_cast<std::size_t>(i)];
  auto p = [&](int k) { return Vec3(base_.row(c.corner[static_cast<std::size_t>(k)]).transpose()); };
  auto n = [&](int k) { return Vec3(normal_.row(c.corner[static_cast<std::size_t>(k)]).transpose()); };
  const double h = min_ratio == -std::numeric_limits<double>::infinity()
                       ? c.h
                       : multires::safe_height(multires::offset_jacobian_ray(p(0), p(1), p(2), n(0), n(1), n(2), c.w[0],
                                                                              c.w[1], c.w[2]),
                                               c.h, min_ratio);
  out[local_global_[static_cast<std::size_t>(i)]] =
      c.w[0] * (p(0) + h * n(0)) + c.w[1] * (p(1) + h * n(1)) + c.w[2] * (p(2) + h * n(2));
  return h != c.h ? 1 : 0;
}

void MultiresSolver::evaluate(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                              const Progress& progress) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("multiresolution evaluate: positions have " + std::to_string(positions.size()) +
                       " entries, the mesh has " + std::to_string(n_vertices_) + " vertices");
  const auto t0 = Clock::now();
  update_base(transforms, model_ ? Base::ModelSolve : Base::Linear, nullptr, progress);
  timings_.base_ms = ms_since(t0);
  add_detail(positions);
}

void MultiresSolver::reconstruct(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<const RowMatrixX3d> base,
                                 VertexData<Vec3>& positions) const {
  if (!model_) throw InvalidInput("multiresolution reconstruct: the base is linear, use evaluate()");
  if (positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("multiresolution reconstruct: positions have " + std::to_string(positions.size()) +
                       " entries, the mesh has " + std::to_string(n_vertices_) + " vertices");
  const auto t0 = Clock::now();
  update_base(transforms, Base::Given, &base);
  timings_.base_ms = ms_since(t0);
  add_detail(positions);
}

void MultiresSolver::add_vertex_frame_detail(Vec3* out) const {
  update_normals();
  const double* b = base_.data();
  const double* nn = normal_.data();
  double* tp = tangent_.data();
  const multires::RingStencil stencil = ring_stencil();
  const auto rows = static_cast<int>(base_.rows());
  const multires::FramePlacement place{b, rows, nn, rows, tp, n_free_, frame_w_.data(), local_global_.data()};
  parallel_for(n_free_, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    // Two passes: the ring's moments, then the normalization and placement, whose square root and
    // division then overlap across vertices instead of waiting on each vertex's gather.
    multires::ring_tangents(stencil, b, rows, nn, static_cast<int>(lo), static_cast<int>(hi), tp);
    multires::place_in_frames(place, static_cast<int>(lo), static_cast<int>(hi), out);
  });
  for (int i : unframed_) {
    const Code& c = codes_[static_cast<std::size_t>(i)];
    out[local_global_[static_cast<std::size_t>(i)]] = Map3(b + 3 * i) + Vec3(c.w[0], c.w[1], c.w[2]);
  }
}

void MultiresSolver::add_detail(VertexData<Vec3>& positions) const {
  const auto t1 = Clock::now();
  Vec3* out = positions.raw().data();
  if (vertex_frames_) {
    add_vertex_frame_detail(out);
    flattened_ = 0;
  } else {
    flattened_ = add_displaced_detail(out);
  }
  for (int l = n_free_; l < n_moving_; ++l) out[local_global_[static_cast<std::size_t>(l)]] = base_.row(l).transpose();
  timings_.detail_ms = ms_since(t1);
}

int MultiresSolver::add_displaced_detail(Vec3* out) const {
  update_normals();
  const double* b = base_.data();
  const double* nn = normal_.data();
  const Code* codes = codes_.data();
  const int* glob = local_global_.data();
  const int n = n_free_;
  std::atomic<int> flattened{0};
  parallel_for(n, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    int local = 0;
    for (auto i = static_cast<int>(lo); i < static_cast<int>(hi); ++i) {
      const Code& c = codes[i];
      const Vec3 pa = Map3(b + 3 * c.corner[0]);
      Vec3 x;
      if (c.corner[2] >= 0) {
        const Vec3 pb = Map3(b + 3 * c.corner[1]), pc = Map3(b + 3 * c.corner[2]);
        const Vec3 na = Map3(nn + 3 * c.corner[0]), nb = Map3(nn + 3 * c.corner[1]), nc = Map3(nn + 3 * c.corner[2]);
        // The offset triangle's corners; its normal against the interpolated base normal is the
        // cheap fold test against the rest-scaled floor (the exact test, with the current a0, is in
        // safe_height): flatten only where the offset map nears a fold.
        const Vec3 qa = pa + c.h * na, qb = pb + c.h * nb, qc = pc + c.h * nc;
        if ((qa - qc).cross(qb - qc).dot(c.w[0] * na + c.w[1] * nb + c.w[2] * nc) < c.min_det) [[unlikely]] {
          local += flatten_detail(i, out);
          continue;
        }
        x = c.w[0] * qa + c.w[1] * qb + c.w[2] * qc;
      } else if (c.corner[1] >= 0) {
        const Vec3 nrm = Map3(nn + 3 * c.corner[0]);
        Vec3 e = Map3(b + 3 * c.corner[1]) - pa;
        e -= e.dot(nrm) * nrm;
        const double len = e.norm();
        if (len > 0.0) e /= len;
        x = pa + c.w[0] * e + c.w[1] * nrm.cross(e) + c.w[2] * nrm;
      } else {
        x = pa + Vec3(c.w[0], c.w[1], c.w[2]);
      }
      out[glob[i]] = x;
    }
    flattened += local;
  });
  return flattened;
}

MultiresProblems MultiresSolver::problems(const VertexData<Vec3>& positions) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("multiresolution problems: positions have " + std::to_string(positions.size()) +
                       " entries, the mesh has " + std::to_string(n_vertices_) + " vertices");
  const Vec3* p = positions.raw().data();
  int flipped = 0;
  const int nd = static_cast<int>(detail_faces_.size());
#pragma omp parallel for schedule(static) reduction(+ : flipped) if (nd > kParallelRows) num_threads(thread_budget())
  for (int k = 0; k < nd; ++k) {
    const Vec3& p0 = p[detail_face_global_[3 * static_cast<std::size_t>(k)]];
    const Vec3& p1 = p[detail_face_global_[3 * static_cast<std::size_t>(k) + 1]];
    const Vec3& p2 = p[detail_face_global_[3 * static_cast<std::size_t>(k) + 2]];
    const double d = (p1 - p0).cross(p2 - p0).dot(base_face_normal(detail_faces_[static_cast<std::size_t>(k)]));
    if (detail_rest_sign_[static_cast<std::size_t>(k)] > 0 && !(d > 0)) ++flipped;
  }
  return {flipped, flattened_};
}

void MultiresSolver::base_positions(VertexData<Vec3>& positions) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("multiresolution base_positions: wrong number of positions");
  for (int l = 0; l < n_moving_; ++l) positions[Vertex(local_global_[static_cast<std::size_t>(l)])] = base_.row(l).transpose();
}

}  // namespace freeform
