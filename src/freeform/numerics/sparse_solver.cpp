// SparseSolver: CHOLMOD supernodal LLT / UMFPACK LU when SuiteSparse is available, Eigen's
// SimplicialLDLT / SparseLU otherwise (or when forced). Failures become SolverError.
#include "freeform/numerics/sparse_solver.h"

#include "freeform/common/error.h"
#include "freeform/common/held_threads.h"
#include "freeform/common/huge_pages.h"
#include "freeform/common/memory_limit.h"
#include "freeform/common/parallel.h"
#include "freeform/common/serial_openmp.h"
#include "freeform/numerics/nested_dissection.h"
#include "freeform/numerics/permuted_lower.h"
#include "freeform/numerics/supernodal_solve.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#if FREEFORM_HAVE_SUITESPARSE
#include "freeform/numerics/cholmod_view.h"
#include "freeform/numerics/supernodal_analysis.h"
#include "freeform/numerics/supernodal_factorization.h"

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace freeform {

using SpMat = Eigen::SparseMatrix<double>;

// Each entry against its mirror, found by binary search in the mirror's column: no transposed
// copy, columns in parallel.
bool is_symmetric(const SpMat& a, double tol) {
  if (a.rows() != a.cols()) return false;
  SpMat c;
  const SpMat* m = &a;
  if (!a.isCompressed()) {
    c = a;
    c.makeCompressed();
    m = &c;
  }
  const int n = static_cast<int>(m->cols());
  const int* outer = m->outerIndexPtr();
  const int* inner = m->innerIndexPtr();
  const double* value = m->valuePtr();
  std::atomic<std::uint64_t> max_bits{0};  // the largest |entry| (non-negative doubles order as their bits)
  parallel_for(n, 8192, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    double mx = 0.0;
    for (auto t = outer[begin]; t < outer[end]; ++t) mx = std::max(mx, std::abs(value[t]));
    const auto bits = std::bit_cast<std::uint64_t>(mx);
    std::uint64_t seen = max_bits.load();
    while (bits > seen && !max_bits.compare_exchange_weak(seen, bits)) {
    }
  });
  const double max_abs = std::bit_cast<double>(max_bits.load());
  if (max_abs == 0.0) return true;
  if (!(max_abs <= std::numeric_limits<double>::max())) return false;  // NaN or infinite entries
  const double bound = tol * max_abs;
  std::atomic<bool> symmetric{true};
  parallel_for(n, 8192, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto j = static_cast<int>(begin); j < end && symmetric.load(std::memory_order_relaxed); ++j)
      for (int t = outer[j]; t < outer[j + 1]; ++t) {
        const int i = inner[t];
        const int* first = inner + outer[i];
        const int* last = inner + outer[i + 1];
        const int* q = std::lower_bound(first, last, j);
        const double mirror = q != last && *q == j ? value[q - inner] : 0.0;
        if (!(std::abs(value[t] - mirror) <= bound)) {
          symmetric = false;
          return;
        }
      }
  });
  return symmetric;
}

namespace {

using Ldlt = Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Eigen::AMDOrdering<int>>;
using Lu = Eigen::SparseLU<SpMat, Eigen::COLAMDOrdering<int>>;
#if FREEFORM_HAVE_SUITESPARSE
// Eigen's factorize() dereferences CHOLMOD's factor without checking it: when the analysis fails
// (the factor is null) that was a crash. This exposes the factor so try_factor can check first.
struct Cholmod : Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> {
  bool has_factor() const { return this->m_cholmodFactor != nullptr; }
  // analyzePattern with a fill-reducing ordering computed elsewhere (CHOLMOD still postorders
  // it by its elimination tree and finds the supernodes), its permuted copies made on all cores.
  void analyze_given(const SpMat& lower, const std::vector<int>& perm) {
    if (this->m_cholmodFactor) cholmod_free_factor(&this->m_cholmodFactor, &this->cholmod());
    const cholmod_sparse a = Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
    this->m_cholmodFactor = analyze_supernodal_given(a, perm.data(), &this->cholmod());
    this->m_isInitialized = true;
    this->m_info = Eigen::Success;
    this->m_analysisIsOk = true;
    this->m_factorizationIsOk = false;
  }
  // factorize() with the permuted copy of the matrix made on all cores (numerics/permuted_lower.h)
  // instead of by CHOLMOD on one thread, and (FactorKernel::Auto) the numeric factorization's
  // subtrees on all cores too, with `schedule` made for the factor's tree, where two threads are
  // free (on 2 cores beside the ordering ahead one is: CHOLMOD's then). On one thread this is
  // CHOLMOD's factorize(): its own copy is as fast (docs/benchmarks.md).
  void factorize_permuted(const SpMat& lower, FactorKernel kernel, std::optional<SupernodalSolve>& schedule) {
    cholmod_factor* l = this->m_cholmodFactor;
    if (thread_budget() < 2 || !l->is_super || l->itype != CHOLMOD_INT || !lower.isCompressed())
      return this->factorize(lower);
    this->m_info = Eigen::NumericalIssue;
    TriangleCsc p;
    try {
      p = permuted_lower(static_cast<int>(lower.rows()), lower.outerIndexPtr(), lower.innerIndexPtr(),
                         lower.valuePtr(), static_cast<const int*>(l->Perm));
    } catch (const std::bad_alloc&) {
      this->cholmod().status = CHOLMOD_OUT_OF_MEMORY;
      return;
    }
    // CHOLMOD first writes the factor's values supernode by supernode on one thread, and the
    // kernel zeroes each fresh page on the thread that touches it (seconds for the gigabytes of
    // a large factor): the values are allocated and touched on all cores first.
    if (l->xtype == CHOLMOD_PATTERN) {
      if (!cholmod_change_factor(CHOLMOD_REAL, 1, 1, 1, 1, l, &this->cholmod())) return;
      double* x = static_cast<double*>(l->x);
      parallel_for(static_cast<std::ptrdiff_t>(l->xsize), std::ptrdiff_t{1} << 18,
                   [x](std::ptrdiff_t begin, std::ptrdiff_t end) { std::fill(x + begin, x + end, 0.0); });
    }
    if (kernel == FactorKernel::Auto && l->is_ll && threads_free() >= 2) {
      schedule.emplace(*supernodal());
      if (schedule->ok()) {
        l->minor = static_cast<std::size_t>(
            supernodal_factorize(*supernodal(), static_cast<double*>(l->x), *schedule, p, this->m_shiftOffset[0]));
        this->m_info = l->minor == l->n ? Eigen::Success : Eigen::NumericalIssue;
        this->m_factorizationIsOk = true;
        return;
      }
      schedule.reset();
    }
    cholmod_sparse s = cholmod_lower_view(static_cast<std::size_t>(lower.rows()), p.inner.size(), p.outer.data(),
                                          p.inner.data(), p.value.data());
    const BlasThreads blas(threads_free());  // beside the ordering ahead: the cores it leaves
    cholmod_super_numeric(&s, nullptr, this->m_shiftOffset, l, &this->cholmod());
    this->m_info = l->minor == l->n ? Eigen::Success : Eigen::NumericalIssue;
    this->m_factorizationIsOk = true;
  }
  std::string ordering;  // how the analysis ordered the rows
  // The factor in SupernodalSolve's terms; nullopt unless it is a supernodal LL' with int indices.
  std::optional<SupernodalFactor> supernodal() const {
    const cholmod_factor* l = this->m_cholmodFactor;
    if (!l || !l->is_super || !l->is_ll || l->itype != CHOLMOD_INT || l->xtype != CHOLMOD_REAL ||
        l->dtype != CHOLMOD_DOUBLE || !l->x)
      return std::nullopt;
    return SupernodalFactor{static_cast<int>(l->n), static_cast<int>(l->nsuper), static_cast<const int*>(l->super),
                            static_cast<const int*>(l->pi), static_cast<const int*>(l->px),
                            static_cast<const int*>(l->s), static_cast<const double*>(l->x),
                            static_cast<const int*>(l->Perm)};
  }
};
using CholmodPtr = std::unique_ptr<Cholmod>;  // Eigen's CHOLMOD objects cannot be moved
// 64-bit indices (umfpack_dl_*): with 32-bit ones the LU of a 300k-row k = 3 system ran out of
// index space and fell back to Eigen's SparseLU (132 s instead of seconds).
using UmfMat = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
using Umf = Eigen::UmfPackLU<UmfMat>;

// CHOLMOD's and UMFPACK's factors and workspaces (3.6 GB at 1M free, k = 3) on huge pages. The
// blocks stay std::malloc's, so the switch is safe at any time, even with blocks outstanding.
void use_huge_pages_in_suitesparse() {
  static const bool done = [] {
    SuiteSparse_config.malloc_func = malloc_huge;
    SuiteSparse_config.calloc_func = calloc_huge;
    SuiteSparse_config.realloc_func = realloc_huge;
    SuiteSparse_config.free_func = std::free;
    return true;
  }();
  (void)done;
}
#endif

const char* kind_name(SolverKind k) {
  switch (k) {
    case SolverKind::CholmodSupernodal: return "cholmod-supernodal-llt";
    case SolverKind::EigenLDLT: return "eigen-simplicial-ldlt";
    case SolverKind::Umfpack: return "umfpack-lu";
    case SolverKind::EigenSparseLU: return "eigen-sparselu";
    case SolverKind::Auto: break;
  }
  return "auto";
}

// solve()'s bound on the relative residual, and the refinement steps it may take to meet it.
// A solve that misses it is still taken when its normwise backward error is within
// kMaxBackwardError: the exact solution of a nearby system, as accurate as the matrix's
// conditioning allows (the order-3 operator of a CAD part's needle fans, docs/bcm.md). How
// accurate that is, the caller estimates (BcmSolver's forward error against the unassembled
// operator).
constexpr double kMaxResidual = 1e-6;
constexpr int kRefinementSteps = 8;
constexpr double kMaxBackwardError = 1e-12;
// Mean nonzeros per row below which CHOLMOD orders by AMD alone (a triangle mesh's Laplacian
// has ~7, the k = 2 operator ~19).
constexpr Eigen::Index kLaplacianLikeNonzeros = 10;
// Rows from which a wider stencil is ordered by METIS without CHOLMOD's trial AMD ordering.
constexpr Eigen::Index kMetisOnlyRows = 250000;
// Rows from which a Laplacian-like stencil's AMD ordering is split into parts on several cores.
constexpr Eigen::Index kParallelAmdRows = 100000;

bool is_cholesky(SolverKind k) { return k == SolverKind::CholmodSupernodal || k == SolverKind::EigenLDLT; }

// FNV-1a over a compressed matrix's pattern: SparseSolver checks that A is the matrix a
// CholeskyAnalysis was made for.
std::uint64_t pattern_hash(const SpMat& a) {
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](std::int64_t v) {
    h ^= static_cast<std::uint64_t>(v);
    h *= 1099511628211ULL;
  };
  mix(a.rows());
  mix(a.cols());
  for (Eigen::Index j = 0; j <= a.outerSize(); ++j) mix(a.outerIndexPtr()[j]);
  for (Eigen::Index t = 0; t < a.nonZeros(); ++t) mix(a.innerIndexPtr()[t]);
  return h;
}

#if FREEFORM_HAVE_SUITESPARSE
// Set once a supernodal factorization ran: OpenBLAS keeps its work buffers, already counted in
// the process's size from then on.
std::atomic<bool> blas_buffers_reserved{false};

// Address space a supernodal factorization takes beyond what the process holds: the factor
// (values and supernode structure, about 12 bytes per entry), CHOLMOD's copy of the matrix and
// its update workspace (a third more), and OpenBLAS's buffers on the first factorization.
std::size_t factorization_bytes(double factor_entries, const SpMat& lower) {
  const double bytes = 16.0 * factor_entries + 24.0 * static_cast<double>(lower.nonZeros());
  return static_cast<std::size_t>(bytes) + (blas_buffers_reserved ? 0 : blas_buffer_bytes());
}

// A CHOLMOD supernodal solver analyzed for `lower` (a lower triangle; values unused); null on
// failure, with CHOLMOD's status in *status.
CholmodPtr analyzed_cholmod(const SpMat& lower, int* status = nullptr) {
  use_huge_pages_in_suitesparse();
  auto s = std::make_unique<Cholmod>();
  s->cholmod().print = 0;  // failures are reported through SolverError, not stderr
  s->cholmod().supernodal = CHOLMOD_SUPERNODAL;
  // CHOLMOD's default tries METIS after AMD when AMD's flops per factor entry pass 500.
  // On Laplacian-like stencils (a k = 1 system, the multiresolution membrane) that happens
  // near 1M rows, where METIS took 8.6 s to save 1.5 s of factorization: AMD alone. On wide
  // k >= 2 stencils METIS pays for itself: CHOLMOD chose it for k = 2 at 300k rows and k = 3
  // from 140k on, after a trial AMD ordering that cost 0.3-0.4 s at 300k and 3.4 s at 1M;
  // from 250k rows on, METIS alone.
  const Eigen::Index nonzeros = 2 * lower.nonZeros() - lower.rows();
  if (nonzeros < kLaplacianLikeNonzeros * lower.rows()) {
    s->cholmod().nmethods = 1;
    s->cholmod().method[0].ordering = CHOLMOD_AMD;
  } else if (lower.rows() >= kMetisOnlyRows) {
    s->cholmod().nmethods = 1;
    s->cholmod().method[0].ordering = CHOLMOD_METIS;
  }
  const SerialOpenMp serial_teams;  // CHOLMOD's 4-thread teams per supernode (serial_openmp.h)
  // METIS orders the whole graph on one thread: with more, its top levels are split and the
  // parts ordered concurrently (nested_dissection.h). One core is left to the caller, which
  // assembles the system meanwhile (bcm/bcm_analysis.h): on 2 cores both are busy already, and
  // two parts there measured no faster than the whole graph (docs/benchmarks.md).
  // AMD on a Laplacian-like stencil is one thread as well, serial on the caller's chain: on
  // large graphs split into 4 parts or more, ordered by AMD concurrently
  // (2 parts can fill more than AMD: test_nested_dissection.cpp).
  const int parts = dissection_parts(thread_budget() - 1);
  const bool amd = s->cholmod().nmethods == 1 && s->cholmod().method[0].ordering == CHOLMOD_AMD;
  std::vector<int> perm;
  if (parts > 1 && s->cholmod().method[0].ordering == CHOLMOD_METIS) perm = nested_dissection(lower, parts);
  if (parts >= 4 && amd && lower.rows() >= kParallelAmdRows)
    perm = nested_dissection(lower, parts, nullptr, LeafOrdering::Amd);
  if (!perm.empty()) {
    s->analyze_given(lower, perm);
    s->ordering = std::string(amd ? "amd" : "metis") + ", " + std::to_string(parts) + " parts in parallel";
  }
  if (perm.empty() || !s->has_factor()) {
    s->analyzePattern(lower);
    const int used = s->cholmod().selected >= 0 ? s->cholmod().method[s->cholmod().selected].ordering : -1;
    s->ordering = used == CHOLMOD_METIS ? "metis" : used == CHOLMOD_AMD ? "amd" : "cholmod";
  }
  if (status) *status = s->cholmod().status;
  if (!s->has_factor() || s->cholmod().status < CHOLMOD_OK) return nullptr;
  return s;
}
#endif

}  // namespace

struct SparseSolver::Impl {
  SpMat a;            // kept for the residual check
  bool lower = false;  // a holds only its lower triangle (every solver tried is a Cholesky one)
  bool reused_analysis = false;
  SolverKind kind = SolverKind::Auto;
#if FREEFORM_HAVE_SUITESPARSE
  std::variant<std::monostate, Ldlt, Lu, CholmodPtr, Umf> f;
  CholmodPtr ahead;  // from a CholeskyAnalysis, used if A has its pattern
  std::uint64_t ahead_hash = 0;
  UmfMat a_long;  // UMFPACK reads the matrix again in every solve, so it must stay alive
#else
  std::variant<std::monostate, Ldlt, Lu> f;
#endif
  std::string failure;  // why the preferred solver failed (for the message)
  std::optional<SupernodalSolve> schedule;  // CHOLMOD's factor solved on several cores
  FactorKernel factor_kernel = FactorKernel::Auto;
  mutable std::once_flag frobenius_once;  // backward_error()
  mutable double frobenius = 0.0;

  Eigen::VectorXd times(const Eigen::VectorXd& x) const {
    if (lower) return a.selfadjointView<Eigen::Lower>() * x;
    return a * x;
  }

  // max_j |A x_j - b_j| / (|A|_F |x_j| + |b_j|): the relative size of the smallest change of A
  // and b that x solves exactly (Rigal and Gaches), which a backward-stable factor keeps near
  // the rounding unit however ill-conditioned A is.
  // |A|_F is computed once, on the first solve that needs it (the nonlinear model checks one
  // solve per start).
  double backward_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& b) const {
    std::call_once(frobenius_once, [this] {
      double sum = 0.0;  // of the whole A where only its lower triangle is stored
      for (int k = 0; k < a.outerSize(); ++k)
        for (SpMat::InnerIterator e(a, k); e; ++e)
          sum += (e.row() != e.col() && lower ? 2.0 : 1.0) * e.value() * e.value();
      frobenius = std::sqrt(sum);
    });
    double worst = 0.0;
    for (Eigen::Index j = 0; j < b.cols(); ++j) {
      const double r = (times(x.col(j)) - b.col(j)).norm();
      const double scale = frobenius * x.col(j).norm() + b.col(j).norm();
      const double e = scale > 0.0 ? r / scale : r;
      worst = std::max(worst, std::isnan(e) ? HUGE_VAL : e);
    }
    return worst;
  }

  // Factor with one kind; returns an empty string on success, else the reason.
  std::string try_factor(SolverKind k) {
    kind = k;
#if FREEFORM_HAVE_SUITESPARSE
    use_huge_pages_in_suitesparse();
#endif
    switch (k) {
      case SolverKind::EigenLDLT: {
        auto& s = f.emplace<Ldlt>();
        s.compute(a);
        if (s.info() != Eigen::Success) return "zero pivot: the matrix is singular";
        const Eigen::VectorXd d = s.vectorD();
        if (!d.allFinite()) return "non-finite pivot";
        if (d.size() > 0 && !(d.minCoeff() > 0.0)) return "the matrix is not positive definite (pivot <= 0)";
        return {};
      }
      case SolverKind::EigenSparseLU: {
        auto& s = f.emplace<Lu>();
        s.compute(a);
        if (s.info() != Eigen::Success) return "the matrix is singular (" + s.lastErrorMessage() + ")";
        return {};
      }
#if FREEFORM_HAVE_SUITESPARSE
      case SolverKind::CholmodSupernodal: {
        auto& s = f.emplace<CholmodPtr>();
        if (ahead && ahead_hash == pattern_hash(a)) {
          s = std::move(ahead);
          reused_analysis = true;
        } else {
          int status = CHOLMOD_OK;
          s = analyzed_cholmod(a, &status);
          if (status == CHOLMOD_OUT_OF_MEMORY)
            throw OutOfMemory("out of memory while ordering a " + std::to_string(a.rows()) + "-row system");
          if (!s) return "the symbolic analysis failed (CHOLMOD status " + std::to_string(status) + ")";
        }
        const auto factorizing = [&] { return "factorizing a " + std::to_string(a.rows()) + "-row system"; };
        require_memory(factorization_bytes(s->cholmod().lnz, a), factorizing);
        const SerialOpenMp serial_teams;  // CHOLMOD's 4-thread teams per supernode (serial_openmp.h)
        s->factorize_permuted(a, factor_kernel, schedule);
        if (s->cholmod().status == CHOLMOD_OUT_OF_MEMORY)
          throw OutOfMemory("out of memory while " + factorizing());
        if (s->info() != Eigen::Success || s->cholmod().status < CHOLMOD_OK)
          return "the matrix is singular or not positive definite";
        blas_buffers_reserved = true;
        if (const auto view = s->supernodal(); view && !schedule) schedule.emplace(*view);
        return {};
      }
      case SolverKind::Umfpack: {
        auto& s = f.emplace<Umf>();
        // Iterative refinement (default 2 steps) made the basis solves as slow as the
        // factorization; the residual check in solve() still guards accuracy.
        s.umfpackControl()(UMFPACK_IRSTEP) = 0;
        a_long = a;
        s.compute(a_long);
        if (s.info() != Eigen::Success) return "the matrix is singular";
        return {};
      }
#else
      case SolverKind::CholmodSupernodal:
      case SolverKind::Umfpack:
        return "SuiteSparse is not available in this build";
#endif
      case SolverKind::Auto: break;
    }
    return "unknown solver kind";
  }
};

struct CholeskyAnalysis::Impl {
#if FREEFORM_HAVE_SUITESPARSE
  CholmodPtr solver;
#endif
  std::uint64_t hash = 0;
};

CholeskyAnalysis::CholeskyAnalysis(const SpMat& lower_pattern) : impl_(std::make_unique<Impl>()) {
#if FREEFORM_HAVE_SUITESPARSE
  if (lower_pattern.rows() != lower_pattern.cols() || !lower_pattern.isCompressed())
    throw InvalidInput("CholeskyAnalysis: the pattern must be square and compressed");
  impl_->hash = pattern_hash(lower_pattern);
  impl_->solver = analyzed_cholmod(lower_pattern);
#else
  (void)lower_pattern;
#endif
}
CholeskyAnalysis::~CholeskyAnalysis() = default;
bool CholeskyAnalysis::ok() const {
#if FREEFORM_HAVE_SUITESPARSE
  return impl_->solver != nullptr;
#else
  return false;
#endif
}

SparseSolver::SparseSolver(SpMat&& matrix, bool symmetric, SolverKind kind, CholeskyAnalysis* analysis,
                           FactorKernel factor_kernel)
    : impl_(std::make_unique<Impl>()) {
  impl_->a.swap(matrix);
  impl_->factor_kernel = factor_kernel;
#if FREEFORM_HAVE_SUITESPARSE
  if (analysis && analysis->impl_) {
    impl_->ahead = std::move(analysis->impl_->solver);
    impl_->ahead_hash = analysis->impl_->hash;
  }
#else
  (void)analysis;
#endif
  SpMat& a = impl_->a;
  if (a.rows() != a.cols() || a.rows() == 0)
    throw InvalidInput("SparseSolver: the matrix must be square and non-empty (got " + std::to_string(a.rows()) + " x " +
                       std::to_string(a.cols()) + ")");
  for (int j = 0; j < a.outerSize(); ++j)
    for (SpMat::InnerIterator it(a, j); it; ++it)
      if (!std::isfinite(it.value())) throw SolverError("SparseSolver: the matrix has non-finite entries");
  if (symmetric && !is_symmetric(a, 1e-10))
    throw InvalidInput("SparseSolver: the matrix was declared symmetric but is not");
  if (!symmetric && is_cholesky(kind))
    throw InvalidInput(std::string("SparseSolver: ") + kind_name(kind) +
                       " needs a symmetric matrix; this one is unsymmetric (use umfpack or eigen-sparselu)");
  a.makeCompressed();

  // Order of attempts: the forced kind alone, or the fast SuiteSparse one then Eigen's.
  std::vector<SolverKind> order;
  if (kind != SolverKind::Auto) {
    order = {kind};
#if !FREEFORM_HAVE_SUITESPARSE
    // Forced SuiteSparse kind without SuiteSparse: use the Eigen counterpart (name() says so).
    if (kind == SolverKind::CholmodSupernodal) order = {SolverKind::EigenLDLT};
    if (kind == SolverKind::Umfpack) order = {SolverKind::EigenSparseLU};
#endif
  } else if (symmetric) {
#if FREEFORM_HAVE_SUITESPARSE
    order = {SolverKind::CholmodSupernodal, SolverKind::EigenLDLT};
#else
    order = {SolverKind::EigenLDLT};
#endif
  } else {
#if FREEFORM_HAVE_SUITESPARSE
    order = {SolverKind::Umfpack, SolverKind::EigenSparseLU};
#else
    order = {SolverKind::EigenSparseLU};
#endif
  }
  // The Cholesky solvers read the lower triangle only: keep just that (222 MB less at 1M free).
  if (std::all_of(order.begin(), order.end(), is_cholesky)) {
    a.prune([](Eigen::Index row, Eigen::Index col, double) { return row >= col; });
    a.data().squeeze();
    impl_->lower = true;
  }
  std::string reasons;
  for (SolverKind k : order) {
    const std::string why = impl_->try_factor(k);
    if (why.empty()) {
      impl_->ahead.reset();  // an analysis for another pattern
      return;
    }
    reasons += std::string(reasons.empty() ? "" : "; ") + kind_name(k) + ": " + why;
  }
  impl_->f = std::monostate{};
  throw SolverError("sparse factorization of a " + std::to_string(a.rows()) + " x " + std::to_string(a.cols()) +
                    " matrix failed (" + reasons + ")");
}

SparseSolver::~SparseSolver() = default;
SparseSolver::SparseSolver(SparseSolver&&) noexcept = default;
SparseSolver& SparseSolver::operator=(SparseSolver&&) noexcept = default;

Eigen::MatrixXd SparseSolver::solve(const Eigen::MatrixXd& b, bool check_residual, SolveKernel kernel,
                                    double* residual) const {
  if (b.rows() != impl_->a.rows())
    throw InvalidInput("SparseSolver::solve: right-hand side has " + std::to_string(b.rows()) + " rows, expected " +
                       std::to_string(impl_->a.rows()));
  if (!b.allFinite()) throw InvalidInput("SparseSolver::solve: right-hand side has non-finite entries");
  Eigen::MatrixXd x = solve_once(b, kernel);
  if (!check_residual && !residual) return x;
  // Residual check: catches a numerically singular matrix the factorization missed.
  double worst = relative_residual(x, b);
  // A factor of needle triangles' operator (a CAD part's) can miss the bound and still be a
  // good enough preconditioner of A: iterative refinement with A recovers the solution where it
  // converges; a singular A's does not. It stops where a step does not lower the residual.
  if (check_residual && !(worst <= kMaxResidual)) {
    Eigen::MatrixXd refined = x;
    for (int step = 0; step < kRefinementSteps && !(worst <= kMaxResidual); ++step) {
      Eigen::MatrixXd r = b;
      parallel_for(b.cols(), 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
        for (std::ptrdiff_t j = lo; j < hi; ++j) r.col(j) -= impl_->times(refined.col(j));
      });
      refined += solve_once(r, kernel);
      const double now = relative_residual(refined, b);
      if (!(now < worst)) break;  // diverging or stalled: the conditioning's limit
      worst = now;
      x = refined;
    }
  }
  if (residual) *residual = worst;
  if (check_residual && !(worst <= kMaxResidual)) {
    const double backward = impl_->backward_error(x, b);
    if (!(backward <= kMaxBackwardError)) {
      char text[96];
      std::snprintf(text, sizeof text, " residual %.2g is too large (backward error %.2g)", worst, backward);
      throw SolverError(std::string("SparseSolver::solve: ") + kind_name(impl_->kind) + text +
                        "; the matrix is (numerically) singular");
    }
  }
  return x;
}

Eigen::MatrixXd SparseSolver::solve_once(const Eigen::MatrixXd& b, SolveKernel kernel) const {
  Eigen::MatrixXd x;
  bool ok = true;
  std::visit(
      [&](auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, std::monostate>) {
          ok = false;
        } else if constexpr (std::is_same_v<S, CholmodPtr>) {
          // cholmod_solve does not survive every failed workspace allocation: refuse up front.
          const auto solving = [&] { return "solving with a " + std::to_string(b.rows()) + "-row factor"; };
          require_memory(static_cast<std::size_t>(4 * 8 * b.size()), solving);
          const auto view = s->supernodal();
          std::optional<Eigen::MatrixXd> parallel;
          if (kernel != SolveKernel::Cholmod && impl_->schedule && impl_->schedule->ok() && view)
            parallel = impl_->schedule->solve(*view, b, kernel == SolveKernel::Auto);
          if (parallel) {
            x = std::move(*parallel);
          } else {
            x = s->solve(b);
            if (s->cholmod().status == CHOLMOD_OUT_OF_MEMORY) throw OutOfMemory("out of memory while " + solving());
            ok = s->info() == Eigen::Success;
          }
        } else {
          x = s.solve(b);
          ok = s.info() == Eigen::Success;
        }
      },
      impl_->f);
  if (!ok) throw SolverError(std::string("SparseSolver::solve: ") + kind_name(impl_->kind) + " failed to solve");
  if (!x.allFinite())
    throw SolverError(std::string("SparseSolver::solve: ") + kind_name(impl_->kind) +
                      " produced non-finite values; the matrix is (numerically) singular");
  return x;
}

double SparseSolver::relative_residual(const Eigen::MatrixXd& x, const Eigen::MatrixXd& b) const {
  // One column per task: the symmetric product from the lower triangle scatters into rows.
  std::vector<double> relative(static_cast<std::size_t>(b.cols()), 0.0);
  parallel_for(b.cols(), 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (std::ptrdiff_t j = lo; j < hi; ++j) {
      const double bn = b.col(j).norm();
      const double r = (impl_->times(x.col(j)) - b.col(j)).norm();
      relative[static_cast<std::size_t>(j)] = bn > 0.0 ? r / bn : r;
    }
  });
  double worst = 0.0;
  for (double r : relative) worst = std::max(worst, std::isnan(r) ? HUGE_VAL : r);
  return worst;
}

SolverKind SparseSolver::kind() const { return impl_->kind; }
Eigen::Index SparseSolver::rows() const { return impl_->a.rows(); }
int SparseSolver::parallel_subtrees() const {
  return impl_->schedule && impl_->schedule->ok() ? impl_->schedule->subtrees() : 0;
}
double SparseSolver::serial_solve_share() const {
  return impl_->schedule && impl_->schedule->ok() ? impl_->schedule->serial_share() : 0.0;
}

std::string SparseSolver::ordering() const {
#if FREEFORM_HAVE_SUITESPARSE
  if (const auto* s = std::get_if<CholmodPtr>(&impl_->f)) return (*s)->ordering;
#endif
  return {};
}

double SparseSolver::factor_nonzeros() const {
#if FREEFORM_HAVE_SUITESPARSE
  if (const auto* s = std::get_if<CholmodPtr>(&impl_->f)) return (*s)->cholmod().lnz;
#endif
  return 0;
}
bool SparseSolver::reused_analysis() const { return impl_->reused_analysis; }
std::string SparseSolver::name() const { return kind_name(impl_->kind); }

}  // namespace freeform
