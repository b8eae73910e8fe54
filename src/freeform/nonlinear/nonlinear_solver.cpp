#include "freeform/nonlinear/nonlinear_solver.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/common/parallel.h"
#include "freeform/nonlinear/anderson.h"
#include "freeform/nonlinear/drift.h"
#include "freeform/nonlinear/enclosed_volume.h"
#include "freeform/nonlinear/face_fans.h"
#include "freeform/nonlinear/part_settings.h"
#include "freeform/nonlinear/ring_smoothing.h"
#include "freeform/nonlinear/rotation.h"

#include <Eigen/SVD>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace freeform {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kParallelRows = 2048;
// Above this many free vertices the volume term's response to the gradient at the iterate is
// solved together with the step (one back-substitution of 6 columns instead of two of 3; the
// solves are most of an iteration there). Below it the response is to the gradient after the
// step, a second back-substitution: with the joint solve at every size, 5 gallery runs stopped
// at the cap at k = 2 and 5 at k = 3 instead of 1 and 2 (docs/nonlinear.md, "What the gallery
// found", 16).
constexpr int kJointVolumeMinFree = 10000;
// Largest uniform scale (and smallest, its inverse) of a handle the model spreads (start()).
constexpr double kMaxHandleScale = 1000.0;

Eigen::Map<const Vec3> row(const double* p, Eigen::Index i) { return Eigen::Map<const Vec3>(p + 3 * i); }

// f(i) for i in [0, n), in parallel above kParallelRows (common/parallel.h: a frame never
// waits for a descheduled thread; the local steps run beside the editor's frames).
template <class F>
void parallel_rows(int n, const F& f) {
  parallel_for(n, kParallelRows / 2, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<int>(lo); i < static_cast<int>(hi); ++i) f(i);
  });
}

// a * x row by row on the pool, each row summed in column order: the bits of Eigen's serial
// product of the column-major a.
void times_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a, const Eigen::MatrixXd& x,
                Eigen::Ref<Eigen::MatrixXd> out) {
  parallel_rows(static_cast<int>(a.rows()), [&](int i) {
    Vec3 sum = Vec3::Zero();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(a, i); e; ++e)
      sum += e.value() * x.row(e.col()).transpose();
    out.row(i) = sum.transpose();
  });
}

// Rows [0, rows) of the rest's Laplacian coordinates with each edge turned by the mean of its ends
// rot(i) (scale times rotation minus the identity): rotated minus rest, exactly zero at rest. An
// edge between a free and a constrained vertex turns with the row's own vertex, not with the mean:
// the constrained (k-1)-ring keeps its constraint's rotation as in linear BCM and the boundary
// stays C^(k-1). (The mean put a 15-degree kink at the fixed strip of the S-bent plane, k = 2, and
// folded its first bumps.)
template <class Rotation>
void rotated_edges(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, const double* rest, int rows, int p,
                   const Rotation& rot, Eigen::MatrixXd& out) {
  parallel_rows(rows, [&](int i) {
    const Eigen::Matrix3d& ri = rot(i);
    Vec3 b = Vec3::Zero();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(lap, i); e; ++e) {
      if (e.col() == i) continue;
      const Eigen::Matrix3d& rj = rot(i >= p || e.col() >= p ? Eigen::Index{i} : e.col());
      b += e.value() * (0.5 * (ri + rj) * (row(rest, e.col()) - row(rest, i)));
    }
    out.row(i) = b.transpose();
  });
}

// The rotation and uniform scale of an affine map's linear part: polar decomposition, scale the
// cube root of |det| (0 where the map is singular).
void rotation_and_scale(const Eigen::Matrix3d& l, Eigen::Quaterniond& q, double& scale) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(l, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0) u.col(2) *= -1.0;
  q = Eigen::Quaterniond(u * svd.matrixV().transpose()).normalized();
  const Eigen::Vector3d sv = svd.singularValues();  // cube roots first: no overflow near 1e300
  scale = std::cbrt(sv(0)) * std::cbrt(sv(1)) * std::cbrt(sv(2));
}

// What a handle's motion T (x -> s R x + t, rotation vector w, scale s) drags, for the volume
// target (start_volumes); its scale about the handle's centre h is set apart, leaving the rigid
// motion x -> R (x - h) + T(h). A turn keeps a limb's volume; it turns about its screw axis
// (Chasles), and the slide along that axis, t's part along w, moves the handle into or out of the body. Where
// that axis passes far from the handle (beyond the support's extent: a small turn about a far
// axis, the accident of a translate gizmo), the motion is a translation: the handle's whole move
// T(h) - h drags (h its centre), so the drag does not jump at w = 0, where it is t. Blended
// between one and two extents; the same in any coordinates.
Vec3 drag(const Eigen::Affine3d& motion, const Vec3& w, double s, const Vec3& h, double extent) {
  const Vec3 move = motion * h - h;
  const Vec3 t = s == 1.0 ? Vec3(motion.translation()) : Vec3(motion * h - motion.linear() * h / s);
  const double angle = w.norm();
  if (!(angle > 0.0)) return t;
  const Vec3 axis = w / angle;
  const Vec3 along = t.dot(axis) * axis, across = t - along;
  // A point of the screw axis, and the handle's distance from the axis.
  const Vec3 point = 0.5 * (across + axis.cross(across) / std::tan(0.5 * angle));
  const Vec3 off = h - point;
  const double far = std::clamp((off - off.dot(axis) * axis).norm() / extent - 1.0, 0.0, 1.0);
  const double blend = far * far * (3.0 - 2.0 * far);
  return along + blend * (move - along);
}

}  // namespace

struct NonlinearSolver::Data {
  std::unique_ptr<BcmFactoredSystem> sys;
  // Local vertices (the BCM patch): rows [0, P) free (BCM order), then the constrained ones.
  int n_inner = 0;                   // rows of sys->lap: the (k-1)-ring
  RowMatrixX3d rest;                 // (P + C) x 3
  RowMatrixX3d x;                    // (P + C) x 3, current
  Eigen::MatrixXd phi;               // P x M: BCM's weight of movable handle m at free vertex i
  std::vector<int> owner;            // per constrained vertex: movable handle or -1
  Eigen::SparseMatrix<double, Eigen::RowMajor> outer;  // sys->outer by rows, for times_rows
  bool residual_checked = false;                       // the factor's backward error, checked once per start
  // The rotation fit's smoothing over the rows of sys->lap: the free vertices, then the
  // constrained (k-1)-ring, whose covariances it also sums (fit_rotations()).
  std::optional<RingSmoothing> smoothing;
  std::optional<FaceFans> fans;      // the rows' triangle fans: the rotation fit and ARAP's right-hand side
  double extent = 1.0;
  // Per local vertex: rotation times scale (free: fitted, warm-started; constrained: the
  // handle's, or the identity), and the free vertices' guidance rotation of the last start.
  std::vector<Eigen::Quaterniond> q, guide;
  std::vector<double> scale;
  std::vector<Eigen::Matrix3d> rot;  // scale * rotation - identity per local vertex (workspace)
  std::vector<Eigen::Matrix3d> means;      // per face of the fans (arap_rows' workspace)
  std::vector<FaceFans::EdgeTerms> terms;  // per face of the fans, with one-sided targets (arap_rows')
  std::vector<Eigen::Matrix3d> cov, cov2;  // workspace of the rotation fit
  // Per free row: the guidance's scale, and the trace of its smoothed rest covariance (the fitted
  // scale's denominator, computed on the first fit where a handle grows; fit_growth()).
  std::vector<double> guide_scale, rest_trace;
  bool grows = false;
  // The membrane term (add_membrane), with each part of the support's settings (part_settings.h):
  // per free row its weight mu and lagged weight (lagged mu); per face of the fans its targets;
  // on the parts with a local membrane its own rotations, fitted to the 1-ring alone (ARAP's
  // local step), the field's elsewhere; its rotated minus rest edges (P x 3).
  Eigen::VectorXd mu, lagged_mu;       // empty: no membrane
  bool lagged = false;                 // some lagged_mu is not 0
  // Per row of the fit (the free rows and the constrained (k-1)-ring): in a part with a local
  // membrane; its part's field_below and field_lean, and the share of the field's rotation its
  // membrane turns with (at least the lean; more where its 1-ring fit is ill-conditioned,
  // fit_rotations()).
  std::vector<char> local_row;
  std::vector<double> field_below, field_lean, field_share;
  bool local_membrane = false;         // some part has one
  std::vector<OneSided> face_targets;  // per face of the fans
  std::vector<Eigen::Quaterniond> q_local;
  std::vector<Eigen::Matrix3d> rot_local;
  Eigen::MatrixXd b_mem;
  Eigen::MatrixXd ac;                // P x 3: A_pc (x_c - x_c rest), fixed during a solve
  Eigen::MatrixXd b1;                // n_inner x 3: rotated minus rest Laplacian coordinates
  RowMatrixX3d last;                 // P x 3: free rows before the last global step
  RowMatrixX3d linear;               // P x 3: linear BCM at the last start's transforms
  // Per movable handle: the rest centre of its rows next to the support (start_volumes; none:
  // the handle moves none of it); its drag and scale about that centre, and the rest moved by
  // them (workspaces).
  std::vector<Vec3> handle_centre;
  std::vector<Eigen::Affine3d> moves;
  std::vector<char> handle_near;
  RowMatrixX3d dragged;
  bool has_linear = false;
  std::optional<EnclosedVolumes> volumes;  // closed components, per support part (with preserve_volume)
  Eigen::MatrixXd grad;              // n_inner x 3: volume gradient (workspace)
  std::optional<AndersonAcceleration> anderson;
  DriftExtrapolation drift;          // moves a sliding iteration on (drift.h)
  bool fitted = false;               // q was fitted to the free rows of x (an image of them may be combined)
  bool accelerated = false;          // x is a combination of images, not a plain image
  bool after_accelerated = false;    // so was the iterate before it (`last`)
  double last_step = 0.0;            // the previous iteration's step, which a confirming step must not exceed
  // The image with the smallest step since the start: what a solve that reaches the cap
  // ends on (in a cycle the last iterate can be its worst point).
  RowMatrixX3d best;
  double best_step = 0.0;

  // Per volume kept (3 columns each), (outer + mu E) times its volume gradient at x: the
  // right-hand sides of the operator's responses u.
  void volume_rhs(int p, Eigen::Ref<Eigen::MatrixXd> out) {
    for (int c = 0; c < volumes->count(); ++c) {
      volumes->gradient(c, x, grad);
      times_rows(outer, grad, out.middleCols(3 * c, 3));
      if (mu.size() > 0) out.middleCols(3 * c, 3) += mu.asDiagonal() * grad.topRows(p);
    }
  }
  // The lagged part of the membrane (add_membrane): lagged mu times its Laplacian rows at the
  // current iterate, which the same extra weight in the operator takes back at a fixed point.
  void add_lagged_membrane(int p, Eigen::Ref<Eigen::MatrixXd> rhs) const {
    parallel_rows(p, [&](int i) {
      const double w = lagged_mu(i);
      if (w == 0.0) return;
      Vec3 sum = Vec3::Zero();
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(sys->lap, i); e; ++e)
        sum += e.value() * (row(x.data(), e.col()) - row(rest.data(), e.col()));
      rhs.row(i) += w * sum.transpose();
    });
  }
  // x is now the image of `last` (if the rotations were fitted to it); the next iterate combines
  // it with the previous images (Anderson), or moves a sliding one on along its step (drift.h),
  // or is the plain image. Like a combination, a moved iterate needs a plain step to confirm
  // convergence, and Anderson's history, of iterates before the jump, goes.
  void accelerate(int p, bool small) {
    Eigen::Map<Eigen::VectorXd> image(x.data(), 3 * Eigen::Index(p));
    const Eigen::Map<const Eigen::VectorXd> at(last.data(), 3 * Eigen::Index(p));
    if (!fitted) {
      anderson->reset();
      drift.reset();
    }
    accelerated = fitted && anderson->next(at, image, !small);
    if (fitted && !accelerated && drift.next(at, image, !small)) {
      accelerated = true;
      anderson->reset();
    }
  }
  // Row i's membrane rotation where its part has a local membrane (scale times rotation minus
  // the identity): its own 1-ring fit, turned toward the field's (a constrained row's: its
  // constraint's) where that fit is ill-conditioned.
  Eigen::Matrix3d local_rotation(std::size_t i) const {
    const Eigen::Quaterniond r = field_share[i] > 0.0 ? q_local[i].slerp(field_share[i], q[i]) : q_local[i];
    return scale[i] * r.toRotationMatrix() - Eigen::Matrix3d::Identity();
  }
  // Adds each component's response times the multiplier that restores its target volume.
  void restore_volumes(int p, const Eigen::MatrixXd& u) {
    for (int c = 0; c < volumes->count(); ++c) {
      const Eigen::MatrixXd uc = u.middleCols(3 * c, 3);
      x.topRows(p) += volumes->multiplier(c, x, uc) * uc;
    }
  }
};

NonlinearSolver::NonlinearSolver(const Mesh& mesh, const Regions& regions, BcmSolver& linear,
                                 const VertexData<Vec3>& rest, const NonlinearOptions& options)
    : d_(std::make_unique<Data>()), options_(options) {
  Data& d = *d_;
  d.sys = linear.release_system();
  if (!d.sys) throw InternalError("NonlinearSolver: the BcmSolver was built without keep_system");
  const std::vector<Vertex>& free = linear.free_vertices();
  n_free_ = static_cast<int>(free.size());
  n_movable_ = linear.n_movable();
  const int p = n_free_, c = static_cast<int>(d.sys->constrained.size());
  d.n_inner = static_cast<int>(d.sys->lap.rows());
  d.outer = d.sys->outer;

  VertexData<int> local(static_cast<std::size_t>(mesh.n_vertices()), -1);
  d.rest.resize(p + c, 3);
  for (int i = 0; i < p; ++i) {
    local[free[static_cast<std::size_t>(i)]] = i;
    d.rest.row(i) = rest[free[static_cast<std::size_t>(i)]].transpose();
  }
  d.owner.resize(static_cast<std::size_t>(c));
  for (int j = 0; j < c; ++j) {
    const Vertex v = d.sys->constrained[static_cast<std::size_t>(j)];
    local[v] = p + j;
    d.rest.row(p + j) = rest[v].transpose();
    const int h = regions.handle_of(v);
    d.owner[static_cast<std::size_t>(j)] = h >= 0 ? regions.movable_index(h) : -1;
  }
  d.x = d.rest;
  // Each connected part of the support with the settings of its own size (part_settings.h).
  const SupportParts parts = support_parts(d.sys->lap, p);
  std::vector<PartSettings> settings;
  std::vector<int> passes;
  for (int free_rows : parts.free) {
    settings.push_back(part_settings(free_rows, d.sys->order, options));
    passes.push_back(settings.back().smoothing_rings);
  }
  if (p + c > 0) d.extent = std::max((d.rest.colwise().maxCoeff() - d.rest.colwise().minCoeff()).norm(), 1e-300);

  // Guidance weights: a translation t moves free vertex i by (sum of its basis row over the
  // handle's 4 frame columns) * t, BCM's own smooth blend of that handle.
  d.phi.resize(p, n_movable_);
  for (int m = 0; m < n_movable_; ++m)
    d.phi.col(m) = linear.basis().middleCols(4 * m, 4).rowwise().sum().cwiseMax(0.0).cwiseMin(1.0);

  // The smoothing over the free vertices and the constrained (k-1)-ring (the rows of the
  // operator's Laplacian), and their triangle fans.
  d.smoothing.emplace(d.sys->lap, passes);
  std::vector<Vertex> global(free.begin(), free.end());
  global.insert(global.end(), d.sys->constrained.begin(), d.sys->constrained.end());
  d.fans.emplace(mesh, local, global, d.rest.data(), d.sys->lap);
  if (p > 0 && std::any_of(settings.begin(), settings.end(), [](const PartSettings& s) { return s.membrane > 0.0; }))
    add_membrane(parts, settings);
  d.q.assign(static_cast<std::size_t>(p + c), Eigen::Quaterniond::Identity());
  d.guide.assign(static_cast<std::size_t>(p), Eigen::Quaterniond::Identity());
  d.scale.assign(static_cast<std::size_t>(p + c), 1.0);
  d.rot.resize(static_cast<std::size_t>(p + c));
  d.cov.resize(static_cast<std::size_t>(d.n_inner));
  d.cov2.resize(static_cast<std::size_t>(d.n_inner));
  if (options.preserve_volume) {
    d.volumes.emplace(mesh, rest, local, p, regions, parts.of_row);
    if (d.volumes->count() == 0) d.volumes.reset();
  }
  d.handle_centre.assign(static_cast<std::size_t>(n_movable_), Vec3::Zero());
  d.handle_near.assign(static_cast<std::size_t>(n_movable_), 0);
  d.moves.resize(static_cast<std::size_t>(n_movable_));
  std::vector<int> near_rows(static_cast<std::size_t>(n_movable_), 0);
  for (int j = 0; j < c; ++j)
    if (const int m = d.owner[static_cast<std::size_t>(j)]; m >= 0) {
      d.handle_centre[static_cast<std::size_t>(m)] += d.rest.row(p + j).transpose();
      ++near_rows[static_cast<std::size_t>(m)];
    }
  for (std::size_t m = 0; m < near_rows.size(); ++m)
    if (near_rows[m] > 0) {
      d.handle_centre[m] /= near_rows[m];
      d.handle_near[m] = 1;
    }
  d.grad = Eigen::MatrixXd::Zero(d.n_inner, 3);
  d.ac = Eigen::MatrixXd::Zero(p, 3);
  d.b1.resize(d.n_inner, 3);
  d.last.resize(p, 3);
  d.anderson.emplace(3 * Eigen::Index(p), std::max(options.acceleration, 0));
}

NonlinearSolver::~NonlinearSolver() = default;

// The volume targets: the rest's, or where a handle is dragged (drag() above the round-off of a
// turn's) or scaled, the rest moved by the drags and scaled about the handles' centres, blended
// through the support by the guidance weights (a shear across a limb keeps its volume; pushed in,
// it loses what it must; a limb whose end shrinks tapers).
void NonlinearSolver::start_volumes(std::span<const Eigen::Affine3d> transforms, std::span<const Vec3> omega,
                                    std::span<const double> handle_s) {
  Data& d = *d_;
  const int p = n_free_, c = static_cast<int>(d.owner.size());
  std::vector<Eigen::Affine3d>& moves = d.moves;
  bool moved = false;
  for (std::size_t m = 0; m < moves.size(); ++m) {
    const Vec3& h = d.handle_centre[m];
    Vec3 t = d.handle_near[m] ? drag(transforms[m], omega[m], handle_s[m], h, d.extent) : Vec3::Zero();
    if (t.norm() <= 1e-12 * d.extent) t.setZero();
    const double s = d.handle_near[m] && std::abs(handle_s[m] - 1.0) > 1e-12 ? handle_s[m] : 1.0;
    // x -> x + t + (s - 1)(x - h), exactly x + t where s is 1.
    moves[m].linear() = s * Eigen::Matrix3d::Identity();
    moves[m].translation() = t + (1.0 - s) * h;
    moved = moved || !t.isZero() || s != 1.0;
  }
  if (!moved) {
    d.volumes->start(transforms, d.x);
    return;
  }
  // moves[m] * r - r, written so that where s is 1 it is t to the bit.
  const auto move = [&](int m, const Vec3& r) {
    const Eigen::Affine3d& a = moves[static_cast<std::size_t>(m)];
    return Vec3(a.translation() + (a(0, 0) - 1.0) * r);
  };
  d.dragged = d.rest;
  parallel_rows(p, [&](int i) {
    const Vec3 r = d.rest.row(i).transpose();
    for (int m = 0; m < n_movable_; ++m) d.dragged.row(i) += d.phi(i, m) * move(m, r).transpose();
  });
  for (int j = 0; j < c; ++j)
    if (const int m = d.owner[static_cast<std::size_t>(j)]; m >= 0)
      d.dragged.row(p + j) += move(m, d.rest.row(p + j).transpose()).transpose();
  d.volumes->start(transforms, d.x, &d.dragged, moves);
}

Eigen::Ref<const NonlinearSolver::RowMatrixX3d> NonlinearSolver::free_positions() const {
  return d_->x.topRows(n_free_);
}

void NonlinearSolver::start(std::span<const Eigen::Affine3d> transforms, bool warm, const RowMatrixX3d* linear) {
  Data& d = *d_;
  if (static_cast<int>(transforms.size()) != n_movable_)
    throw InvalidInput("evaluate: got " + std::to_string(transforms.size()) + " transforms for " +
                       std::to_string(n_movable_) + " movable handles");
  std::vector<Eigen::Quaterniond> handle_q(static_cast<std::size_t>(n_movable_));
  std::vector<Vec3> omega(static_cast<std::size_t>(n_movable_));
  std::vector<double> handle_s(static_cast<std::size_t>(n_movable_), 1.0);
  for (int m = 0; m < n_movable_; ++m) {
    const auto um = static_cast<std::size_t>(m);
    const Eigen::Affine3d& t = transforms[um];
    if (!t.matrix().allFinite()) throw InvalidInput("evaluate: transform " + std::to_string(m) + " is not finite");
    rotation_and_scale(t.linear(), handle_q[um], handle_s[um]);
    // The scale spreads through the support with BCM's weights: a handle of one vertex scaled
    // 1e6 about itself moves nothing in linear BCM but would blow its neighbours up by 1e3-1e6.
    if (!(handle_s[um] >= 1.0 / kMaxHandleScale && handle_s[um] <= kMaxHandleScale))
      throw InvalidInput("evaluate: transform " + std::to_string(m) + " scales by " + json_messages::num(handle_s[um]) +
                         "; the nonlinear model spreads a handle's scale through the support and takes scales "
                         "from 1/" + json_messages::num(kMaxHandleScale) + " to " + json_messages::num(kMaxHandleScale) +
                         " (the linear model takes any)");
    omega[um] = rotation_vector(handle_q[um]);
  }
  const int p = n_free_, c = static_cast<int>(d.owner.size());
  // Constraints with their rotations, and their fixed contribution A_pc (x_c - x_c rest).
  Eigen::MatrixXd dc(c, 3);
  for (int j = 0; j < c; ++j) {
    const int m = d.owner[static_cast<std::size_t>(j)];
    const auto uj = static_cast<std::size_t>(p + j);
    const Vec3 r = d.rest.row(p + j).transpose();
    const Vec3 y = m >= 0 ? Vec3(transforms[static_cast<std::size_t>(m)] * r) : r;
    d.x.row(p + j) = y.transpose();
    dc.row(j) = (y - r).transpose();
    d.q[uj] = m >= 0 ? handle_q[static_cast<std::size_t>(m)] : Eigen::Quaterniond::Identity();
    d.scale[uj] = m >= 0 ? handle_s[static_cast<std::size_t>(m)] : 1.0;
  }
  d.ac = d.sys->a_pc * dc;
  // Guidance: rotation vectors and log scales blended with BCM's weights.
  d.guide_scale.resize(static_cast<std::size_t>(p));
  parallel_rows(p, [&](int i) {
    Vec3 w = Vec3::Zero();
    double ls = 0.0;
    for (int m = 0; m < n_movable_; ++m) {
      w += d.phi(i, m) * omega[static_cast<std::size_t>(m)];
      ls += d.phi(i, m) * std::log(handle_s[static_cast<std::size_t>(m)]);
    }
    const auto ui = static_cast<std::size_t>(i);
    const Eigen::Quaterniond g = rotation_from_vector(w);
    d.q[ui] = warm ? (g * d.guide[ui].conjugate() * d.q[ui]).normalized() : g;
    d.guide[ui] = g;
    d.scale[ui] = d.guide_scale[ui] = std::exp(ls);
  });
  d.grows = std::any_of(d.guide_scale.begin(), d.guide_scale.end(), [](double g) { return g > 1.0; });
  if (d.local_membrane && !warm)
    for (int i = 0; i < d.n_inner; ++i) d.q_local[static_cast<std::size_t>(i)] = d.q[static_cast<std::size_t>(i)];
  if (!warm) d.x.topRows(p) = d.rest.topRows(p);
  if (linear && linear->rows() != p) throw InternalError("NonlinearSolver::start: linear rows do not match");
  if (warm && linear && d.has_linear) d.x.topRows(p) += *linear - d.linear;
  d.has_linear = linear != nullptr;
  if (linear) d.linear = *linear;
  if (d.volumes) start_volumes(transforms, omega, handle_s);
  d.anderson->reset();
  d.drift.reset();
  d.fitted = d.accelerated = d.residual_checked = false;
  d.best_step = std::numeric_limits<double>::infinity();
  state_ = {};
}

const NonlinearState& NonlinearSolver::iterate(int max_iterations, double budget_ms,
                                               const std::atomic<bool>* interrupt) {
  Data& d = *d_;
  const auto t0 = Clock::now();
  const double ms0 = state_.ms;
  const int p = n_free_, n_inner = d.n_inner;
  const auto& lap = d.sys->lap;
  for (int it = 0; it < max_iterations; ++it) {
    // Global step: the rest's Laplacian coordinates with each edge rotated and scaled by the
    // mean of its ends (ARAP's right-hand side), minus the rest's own: exactly zero at rest.
    //   A_pp (x_p - rest_p) = outer * b1 + mu b_mem - A_pc (x_c - rest_c)
    // (mu b_mem: the membrane term, add_membrane: ARAP's spokes-and-rims right-hand side with
    // one-sided targets, turned by its own 1-ring rotations or, on large supports, the field's.)
    const int n_local = static_cast<int>(d.q.size());
    parallel_rows(n_local, [&](int i) {
      const auto ui = static_cast<std::size_t>(i);
      d.rot[ui] = d.scale[ui] * d.q[ui].toRotationMatrix() - Eigen::Matrix3d::Identity();
    });
    const auto field = [](const std::vector<Eigen::Matrix3d>& r) {
      return [&r](Eigen::Index i) -> const Eigen::Matrix3d& { return r[static_cast<std::size_t>(i)]; };
    };
    if (d.sys->order == 1)  // the operator is ARAP's: its own right-hand side
      arap_rows(d.rot, d.b1);
    else
      rotated_edges(lap, d.rest.data(), n_inner, p, field(d.rot), d.b1);
    const int volume_cols = d.volumes ? 3 * d.volumes->count() : 0;
    const bool joint = volume_cols > 0 && p > kJointVolumeMinFree;
    Eigen::MatrixXd both(p, 3 + (joint ? volume_cols : 0));
    auto rhs = both.leftCols(3);
    times_rows(d.outer, d.b1, rhs);
    rhs -= d.ac;
    if (d.mu.size() > 0) {  // the parts with a local membrane turn it with their own rotations
      if (d.local_membrane)
        parallel_rows(n_local, [&](int i) {
          const auto ui = static_cast<std::size_t>(i);
          d.rot_local[ui] = i < n_inner && d.local_row[ui] != 0 ? d.local_rotation(ui) : d.rot[ui];
        });
      arap_rows(d.local_membrane ? d.rot_local : d.rot, d.b_mem, &d.face_targets);
      rhs += d.mu.asDiagonal() * d.b_mem;
      if (d.lagged) d.add_lagged_membrane(p, rhs);
    }
    if (joint) d.volume_rhs(p, both.rightCols(volume_cols));
    // The backward error depends on the factor far more than on the right-hand side: the
    // first step after a start checks it, the others reuse that check.
    const Eigen::MatrixXd solution = d.sys->solver.solve(both, !d.residual_checked);
    d.residual_checked = true;
    d.last = d.x.topRows(p);
    d.x.topRows(p) = d.rest.topRows(p) + solution.leftCols(3);
    if (joint)
      d.restore_volumes(p, solution.rightCols(volume_cols));
    else if (d.volumes)
      keep_volumes();
    state_.step = p > 0 ? (d.x.topRows(p) - d.last).rowwise().norm().maxCoeff() / d.extent : 0.0;
    ++state_.iterations;
    // Not on the first step after a start: its move is measured from the warm start's
    // prediction, which can be close to the new iterate while both are far from the solution.
    // Not at an accelerated iterate either: Anderson mixing also finds fixed points that plain
    // iteration leaves (on the editor benchmark's bunny twist one 6 % of the diagonal from
    // where the model settles); a plain step from it must confirm, its move not growing.
    const bool small = state_.step <= options_.tolerance && state_.iterations > 1;
    state_.converged = small && !d.accelerated && (!d.after_accelerated || state_.step <= d.last_step);
    if (!state_.converged && state_.step < d.best_step && state_.iterations > 1) {
      d.best_step = state_.step;
      d.best = d.x.topRows(p);
    }
    if (!state_.converged && state_.iterations >= options_.max_iterations && d.best_step < state_.step) {
      d.x.topRows(p) = d.best;  // at the cap: the best image since the start
      state_.step = d.best_step;
      d.fitted = d.accelerated = false;
      d.anderson->reset();
      state_.ms = ms0 + std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      break;
    }
    d.after_accelerated = d.accelerated;
    d.last_step = state_.step;
    const bool interrupted = interrupt && interrupt->load(std::memory_order_relaxed);
    // Before any other break: the next call starts with a fresh fit.
    if (!state_.converged && !interrupted) {
      d.accelerate(p, small);
      fit_rotations();
      d.fitted = true;
    } else {
      d.fitted = d.accelerated = false;
    }
    state_.ms = ms0 + std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (state_.converged || interrupted || state_.ms - ms0 >= budget_ms) break;
  }
  return state_;
}

// Adds mu times ARAP's energy, sum w_ij |e_ij - R e_ij rest|^2, whose gradient is -(L x - b(R)),
// to the global step's: the operator becomes (outer + sigma mu E) * lap, E selecting the free
// rows, sigma giving mu E lap the sign of A_pp's diagonal, mu = weight * mean |diag A_pp| /
// mean |diag L_pp| (the ratio at the scale of a ring); the right-hand side gains mu b(R) on the
// free rows. Both energies vanish at rest and move rigidly with the constraints: identity and
// rigid edits are unchanged. Each part of the support has its own weight, ratio and targets (no
// entry of lap joins two parts, so A_pp stays symmetric). Factors the new A_pp.
void NonlinearSolver::add_membrane(const SupportParts& parts, const std::vector<PartSettings>& settings) {
  Data& d = *d_;
  const int p = n_free_, n = static_cast<int>(d.sys->lap.cols());
  const auto part = [&parts](Eigen::Index row) {
    return static_cast<std::size_t>(parts.of_row[static_cast<std::size_t>(row)]);
  };
  Eigen::SparseMatrix<double> membrane = d.sys->lap.topRows(p);  // E * lap
  Eigen::SparseMatrix<double> full = d.sys->outer * d.sys->lap;
  std::vector<double> da(settings.size(), 0.0), dl(settings.size(), 0.0), mu(settings.size());
  for (int i = 0; i < p; ++i) {
    da[part(i)] += full.coeff(i, i);
    dl[part(i)] += membrane.coeff(i, i);
  }
  for (std::size_t c = 0; c < mu.size(); ++c) {
    const double sign = (da[c] > 0.0) == (dl[c] > 0.0) ? 1.0 : -1.0;
    mu[c] = sign * settings[c].membrane * std::abs(da[c]) / std::max(std::abs(dl[c]), 1e-300);
  }
  d.mu.resize(p);
  d.lagged_mu.resize(p);
  const auto rows = static_cast<std::size_t>(d.n_inner);
  d.local_row.resize(rows);
  d.field_below.resize(rows);
  d.field_lean.assign(rows, 0.0);
  d.field_share.assign(rows, 0.0);
  for (int i = 0; i < p; ++i) {
    d.mu(i) = mu[part(i)];
    d.lagged_mu(i) = settings[part(i)].lagged * mu[part(i)];
  }
  // Measured on the gallery (docs/nonlinear.md, 12): with the 1-ring rotations the membrane is
  // ARAP itself, and k = 3 collapses a third fewer faces than with the smoothed ones, as many
  // folds (with the spokes-only ARAP of before it folded twice as many). As in ARAP, the
  // constrained (k-1)-ring fits its own too where its boundary is at least C1: turned with the
  // constraint's rotation, the faces next to it squeezed more. At a crease (C0) the bending
  // term does not hold them to the constraint's tangent plane and the membrane still does:
  // fitted there they folded (docs/nonlinear.md, "What the gallery found", 53).
  for (std::size_t i = 0; i < rows; ++i) {
    const PartSettings& s = settings[part(static_cast<Eigen::Index>(i))];
    d.local_row[i] = s.local_membrane ? 1 : 0;
    if (i < static_cast<std::size_t>(p)) {
      d.field_below[i] = s.field_below;  // 0 without a local membrane
      d.field_share[i] = d.field_lean[i] = s.field_lean;
    } else {
      d.field_below[i] = 0.0;
      d.field_share[i] = 1.0 - std::clamp(d.sys->smoothness[i - static_cast<std::size_t>(p)], 0.0, 1.0);
    }
  }
  for (int k = 0; k < membrane.outerSize(); ++k)  // the operator holds (1 + lagged) mu of it
    for (Eigen::SparseMatrix<double>::InnerIterator e(membrane, k); e; ++e)
      e.valueRef() = (1.0 + settings[part(e.row())].lagged) * mu[part(e.row())] * e.value();
  full += membrane;
  Eigen::SparseMatrix<double> app = full.leftCols(p), apc = full.rightCols(n - p);
  const bool symmetric = is_symmetric(app, 1e-10);
  d.sys->solver = SparseSolver(std::move(app), symmetric);
  d.sys->a_pc.swap(apc);
  d.lagged = (d.lagged_mu.array() != 0.0).any();
  d.local_membrane = std::any_of(d.local_row.begin(), d.local_row.end(), [](char l) { return l != 0; });
  if (d.local_membrane) {
    d.q_local.assign(rows, Eigen::Quaterniond::Identity());
    d.rot_local.resize(static_cast<std::size_t>(p) + d.owner.size());  // the constrained ones: their own
  }
  d.face_targets.resize(static_cast<std::size_t>(d.fans->n_faces()));
  for (int f = 0; f < d.fans->n_faces(); ++f) {  // a face's corners among the rows lie in one part
    const std::array<int, 3>& corners = d.fans->corners(f);
    const int row = *std::min_element(corners.begin(), corners.end());
    d.face_targets[static_cast<std::size_t>(f)] = settings[part(row)].targets;
  }
  d.b_mem.resize(p, 3);
}

// ARAP's rotated minus rest Laplacian coordinates of the free rows (face_fans.h): the edges to
// constrained vertices turn with the mean of both ends, as in ARAP's energy (the bending term's
// C^(k-1) boundary rule is not the membrane's: with it, our order 1 folded twice as many edges
// of the gallery; docs/nonlinear.md, "What the gallery found", 12). targets (null: fixed
// targets): per face, how each edge's target follows its stretch at the current iterate
// (face_fans.h).
void NonlinearSolver::arap_rows(const std::vector<Eigen::Matrix3d>& rot, Eigen::MatrixXd& out,
                                const std::vector<OneSided>* targets) {
  Data& d = *d_;
  out.resize(n_free_, 3);
  const auto faces = static_cast<std::size_t>(d.fans->n_faces());
  if (targets) {  // each edge's term once per face, not once per row at either end
    d.terms.resize(faces);
    parallel_rows(d.fans->n_faces(), [&](int f) {
      const auto uf = static_cast<std::size_t>(f);
      OneSided target = (*targets)[uf];
      if (target.bent_stretch_share > target.stretch_share)  // the field's rotations tell bends from twists
        target = FaceFans::where_bent(target, d.fans->bend_fraction(f, d.q, d.rest.data()));
      if (target.growth_taken) {
        const auto& c = d.fans->corners(f);
        const auto scale = [&](int k) { return d.scale[static_cast<std::size_t>(k)]; };
        target.grown = (scale(c[0]) + scale(c[1]) + scale(c[2])) / 3.0;
      }
      d.terms[uf] = d.fans->edge_terms(f, d.fans->mean(f, rot), d.rest.data(), d.x.data(), target);
    });
    parallel_rows(n_free_, [&](int i) { out.row(i) = d.fans->rotated(i, d.terms).transpose(); });
    return;
  }
  d.means.resize(faces);
  parallel_rows(d.fans->n_faces(), [&](int f) { d.means[static_cast<std::size_t>(f)] = d.fans->mean(f, rot); });
  parallel_rows(n_free_, [&](int i) { out.row(i) = d.fans->rotated(i, d.rest.data(), d.means).transpose(); });
}

void NonlinearSolver::keep_volumes() {
  // Per volume kept, the operator's response u to the volume gradient after the step
  // (one more back-substitution, 3 columns each), added with the multiplier that restores the
  // target volume. On large supports iterate() solves the response to the gradient before the
  // step together with the step instead (kJointVolumeMinFree).
  Data& d = *d_;
  const int p = n_free_;
  Eigen::MatrixXd rhs(p, 3 * d.volumes->count());
  d.volume_rhs(p, rhs);
  // No residual check: the same factor's was checked (iterate).
  d.restore_volumes(p, d.sys->solver.solve(rhs, false));
}

void NonlinearSolver::fit_rotations() {
  Data& d = *d_;
  const int p = n_free_;
  const double* x = d.x.data();
  parallel_rows(d.n_inner, [&](int i) { d.cov[static_cast<std::size_t>(i)] = d.fans->covariance(i, x); });
  if (d.local_membrane)  // the membrane's rotations: the 1-ring alone
    parallel_rows(d.n_inner, [&](int i) {
      const auto ui = static_cast<std::size_t>(i);
      if (d.local_row[ui] == 0) return;
      extract_rotation(d.cov[ui], d.q_local[ui]);
      // Without a threshold (and on the constrained rows) the share stays as add_membrane set it.
      if (const double below = d.field_below[ui]; below > 0.0)
        d.field_share[ui] =
            std::clamp(2.0 * (below - fit_conditioning(d.cov[ui], d.q_local[ui])) / below, d.field_lean[ui], 1.0);
    });
  // Summing the neighbours' covariances ring by ring fits R_i to a wider patch: a smoother
  // rotation field (like SR-ARAP's smoothness term), fewer iterations, less necking. The
  // constrained (k-1)-ring takes part with its own deformed 1-rings: summed over the free side
  // alone, the patch of a vertex near the fixed rim would lean toward the rotated interior and
  // that of a vertex near a handle toward the less rotated one (the gallery, docs/nonlinear.md).
  d.smoothing->apply(d.cov, d.cov2);
  parallel_rows(p, [&](int i) { extract_rotation(d.cov[static_cast<std::size_t>(i)], d.q[static_cast<std::size_t>(i)]); });
  if (d.grows) fit_growth();
}

void NonlinearSolver::fit_growth() {
  // Where the guidance grows a row (scale g > 1), its scale is fitted with its rotation, as a
  // similarity's is (tr(R^T C) over the rest's tr(C), both smoothed alike), within [1, g]: a
  // band that the geometry keeps short is not forced to grow and buckle, and a grown one is
  // (docs/nonlinear.md, "What the gallery found", 64).
  Data& d = *d_;
  const int p = n_free_;
  if (d.rest_trace.empty()) {
    std::vector<Eigen::Matrix3d> rest(static_cast<std::size_t>(d.n_inner)), work;
    parallel_rows(d.n_inner, [&](int i) { rest[static_cast<std::size_t>(i)] = d.fans->covariance(i, d.rest.data()); });
    d.smoothing->apply(rest, work);
    d.rest_trace.resize(static_cast<std::size_t>(p));
    for (int i = 0; i < p; ++i) d.rest_trace[static_cast<std::size_t>(i)] = rest[static_cast<std::size_t>(i)].trace();
  }
  parallel_rows(p, [&](int i) {
    const auto ui = static_cast<std::size_t>(i);
    const double g = d.guide_scale[ui];
    if (!(g > 1.0 && d.rest_trace[ui] > 0.0)) return;
    const double fitted = (d.q[ui].toRotationMatrix().transpose() * d.cov[ui]).trace() / d.rest_trace[ui];
    d.scale[ui] = std::clamp(fitted, 1.0, g);
  });
}

IterativeModelFactory nonlinear_base_model(const NonlinearOptions& options) {
  NonlinearOptions on_base = options;
  on_base.smooth_rest = true;
  return [on_base](const Mesh& mesh, const Regions& regions, BcmSolver& linear, const VertexData<Vec3>& rest) {
    return std::make_unique<NonlinearSolver>(mesh, regions, linear, rest, on_base);
  };
}

}  // namespace freeform
