#if FREEFORM_HAVE_SUITESPARSE
#include "freeform/numerics/supernodal_analysis.h"

#include "freeform/numerics/cholmod_view.h"
#include "freeform/numerics/permuted_lower.h"

#include <algorithm>
#include <cstddef>
#include <new>
#include <vector>

namespace freeform {
namespace {

// The pattern of one triangle of P A P' as CHOLMOD's permute step would hand it on: the upper
// one with stype 1, the lower one with stype -1.
struct PermutedPattern {
  TriangleCsc csc;
  cholmod_sparse view{};
  PermutedPattern(const cholmod_sparse& lower, const int* perm, Triangle triangle)
      : csc(permuted_triangle(static_cast<int>(lower.nrow), static_cast<const int*>(lower.p),
                              static_cast<const int*>(lower.i), nullptr, perm, triangle)) {
    view = cholmod_lower_view(lower.nrow, csc.inner.size(), csc.outer.data(), csc.inner.data());
    if (triangle == Triangle::upper) view.stype = 1;
  }
};

bool is_permutation(const int* perm, int n) {
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    if (perm[k] < 0 || perm[k] >= n || seen[static_cast<std::size_t>(perm[k])]) return false;
    seen[static_cast<std::size_t>(perm[k])] = 1;
  }
  return true;
}

// cholmod_analyze_p's postorder of the tree weighted by the column counts, composed with the
// ordering: perm, counts and parents relabelled in place.
void weighted_postorder(int n, int* perm, int* count, std::vector<int>& parent, cholmod_common* common) {
  std::vector<int> post(static_cast<std::size_t>(n)), inverse(post.size()), work(post.size());
  if (cholmod_postorder(parent.data(), static_cast<std::size_t>(n), count, post.data(), common) != n) return;
  const auto relabel = [&](int* values) {
    for (std::size_t k = 0; k < work.size(); ++k) work[k] = values[post[k]];
    std::copy(work.begin(), work.end(), values);
  };
  relabel(perm);
  relabel(count);
  for (std::size_t k = 0; k < post.size(); ++k) inverse[static_cast<std::size_t>(post[k])] = static_cast<int>(k);
  for (std::size_t k = 0; k < post.size(); ++k) {
    const int old_parent = parent[static_cast<std::size_t>(post[k])];
    work[k] = old_parent < 0 ? old_parent : inverse[static_cast<std::size_t>(old_parent)];
  }
  parent = work;
}

// The elimination tree, its postorder and the column counts of L for the ordering in L->Perm
// (cholmod_analyze_ordering's steps).
bool count_columns(const cholmod_sparse& lower, cholmod_factor* l, std::vector<int>& parent, cholmod_common* common) {
  const auto n = static_cast<std::size_t>(lower.nrow);
  PermutedPattern triu(lower, static_cast<const int*>(l->Perm), Triangle::upper);
  PermutedPattern tril(lower, static_cast<const int*>(l->Perm), Triangle::lower);
  std::vector<int> post(n), first(n), level(n);
  bool ok = cholmod_etree(&triu.view, parent.data(), common) &&
            cholmod_postorder(parent.data(), n, nullptr, post.data(), common) == static_cast<SuiteSparse_long>(n);
  if (!ok && common->status == CHOLMOD_OK) common->status = CHOLMOD_INVALID;
  return ok && cholmod_rowcolcounts(&tril.view, nullptr, 0, parent.data(), post.data(), nullptr,
                                    static_cast<int*>(l->ColCount), first.data(), level.data(), common);
}

}  // namespace

cholmod_factor* analyze_supernodal_given(const cholmod_sparse& lower, const int* perm, cholmod_common* common) {
  const auto n = static_cast<int>(lower.nrow);
  common->status = CHOLMOD_OK;
  common->selected = -1;
  common->called_nd = 0;
  if (lower.stype >= 0 || lower.itype != CHOLMOD_INT || !lower.packed || !is_permutation(perm, n)) {
    common->status = CHOLMOD_INVALID;
    return nullptr;
  }
  cholmod_factor* l = cholmod_allocate_factor(lower.nrow, common);
  if (!l) return nullptr;
  try {
    std::copy(perm, perm + n, static_cast<int*>(l->Perm));
    std::vector<int> parent(static_cast<std::size_t>(n));
    if (count_columns(lower, l, parent, common)) {
      common->method[0].fl = common->fl;
      common->method[0].lnz = common->lnz;
      common->selected = 0;
      l->ordering = CHOLMOD_GIVEN;
      if (common->postorder)
        weighted_postorder(n, static_cast<int*>(l->Perm), static_cast<int*>(l->ColCount), parent, common);
      PermutedPattern triu(lower, static_cast<const int*>(l->Perm), Triangle::upper);
      PermutedPattern tril(lower, static_cast<const int*>(l->Perm), Triangle::lower);
      cholmod_super_symbolic2(1, &triu.view, &tril.view, parent.data(), l, common);
    }
  } catch (const std::bad_alloc&) {
    common->status = CHOLMOD_OUT_OF_MEMORY;
  }
  if (common->status < CHOLMOD_OK) cholmod_free_factor(&l, common);
  return l;
}

}  // namespace freeform
#endif
