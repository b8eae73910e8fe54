// The peer of BcmSolver::evaluate (issue 13): the basis product written plainly with Eigen, as
// a libigl user writes it, compiled with -march=native (bench/CMakeLists.txt) as that user would.
// Raw pointers in, unaligned maps inside: Eigen objects must not cross between translation units
// built for different ISAs (their alignment assumptions differ: a crash).
#include <Eigen/Core>

void eigen_plain_product(const double* x0, const double* basis, const double* g, double* x, long rows, long n4) {
  using Map = Eigen::Map<const Eigen::MatrixXd, Eigen::Unaligned>;
  Eigen::Map<Eigen::MatrixXd, Eigen::Unaligned> out(x, rows, 3);
  out.noalias() = Map(x0, rows, 3) + Map(basis, rows, n4) * Map(g, n4, 3);
}
