// A fill-reducing ordering of a large symmetric pattern that uses several cores (issue 43).
// METIS's nested dissection (what CHOLMOD runs for wide stencils) is one thread: 19-25 s of the
// 1M-free k = 3 precompute. Here the top levels of the dissection are vertex separators (the
// first, from 100k rows, from METIS on a coarse graph, numerics/coarse_separator.h; the others
// METIS's own bisection), each level's parts split concurrently, and the parts below are ordered
// concurrently, by METIS or, for Laplacian-like stencils, by AMD (what CHOLMOD runs for those,
// one thread as well); separators go last, as METIS places them.
#pragma once

#include <Eigen/SparseCore>

#include <vector>

namespace freeform {

// The ordering of `lower` (a lower triangle, compressed; values unused) as CHOLMOD's Perm
// (position k holds the row eliminated k-th), with `parts` (a power of two) ordered concurrently
// on run_tasks' threads. Empty if it cannot be computed (no SuiteSparse, METIS failed): the
// caller then orders the whole graph.
// times (optional, benchmarks): each task's CPU time, which is its wall time on a core of its
// own: the splits level by level, then the leaves.
struct DissectionTimes {
  std::vector<std::vector<double>> split_ms;
  std::vector<double> leaf_ms;
};
// How the parts below the splits are ordered, and a whole graph in cholesky_fill.
enum class LeafOrdering { Metis, Amd };
std::vector<int> nested_dissection(const Eigen::SparseMatrix<double>& lower, int parts,
                                   DissectionTimes* times = nullptr, LeafOrdering leaves = LeafOrdering::Metis);

// The nonzeros of the Cholesky factor of a matrix with pattern `lower` when its rows are
// eliminated in `perm`'s order (CHOLMOD's symbolic analysis, which postorders it); an empty
// perm: CHOLMOD's ordering of the whole graph by `whole`. 0 without SuiteSparse.
double cholesky_fill(const Eigen::SparseMatrix<double>& lower, std::vector<int> perm,
                     LeafOrdering whole = LeafOrdering::Metis);

// The leaves nested_dissection uses for a thread budget: the smallest power of two at least
// `threads`, at most 64.
int dissection_parts(int threads);

}  // namespace freeform
