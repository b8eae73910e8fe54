// Which sparse factorization to use (numerics/sparse_solver.h).
#pragma once

namespace freeform {

enum class SolverKind { Auto, CholmodSupernodal, EigenLDLT, Umfpack, EigenSparseLU };

}  // namespace freeform
