// A cholmod_sparse over the compressed columns of a symmetric matrix's lower triangle, rows
// sorted, without a copy: what the ordering, the separators and the factorization hand CHOLMOD.
// Only for translation units built with SuiteSparse (FREEFORM_HAVE_SUITESPARSE).
#pragma once

#include <cholmod.h>

#include <cstddef>

namespace freeform {

// values null: the pattern alone. CHOLMOD does not write through the pointers it is given here.
inline cholmod_sparse cholmod_lower_view(std::size_t n, std::size_t nonzeros, const int* outer, const int* inner,
                                         const double* values = nullptr) {
  cholmod_sparse a{};
  a.nrow = a.ncol = n;
  a.nzmax = nonzeros;
  a.p = const_cast<int*>(outer);
  a.i = const_cast<int*>(inner);
  a.x = const_cast<double*>(values);
  a.stype = -1;
  a.itype = CHOLMOD_INT;
  a.xtype = values ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

}  // namespace freeform
