// A vertex separator of a large graph in a fraction of METIS's time (issue 43): METIS's
// bisection of the whole graph coarsens it first, on one thread (1.4 s of the 1M-row k = 3
// ordering on this project's VM). Here one sweep over the edges clusters each vertex with the
// neighbours that share most of its own neighbours (about its 1-ring, in a k-ring stencil), METIS
// bisects the graph of clusters, and the clusters' separator is projected back and thinned to
// the vertices that touch both sides. Slightly longer than METIS's own separator
// (docs/benchmarks.md, "Precompute on all cores").
#pragma once

#include <Eigen/SparseCore>

#include <vector>

namespace freeform {

// Per vertex of `lower` (a lower triangle, compressed; values unused): 0 or 1 for the two parts,
// 2 for the separator; no edge joins parts 0 and 1. Empty if there is no such split (a tiny or
// disconnected graph, METIS failed, no SuiteSparse).
std::vector<int> coarse_separator(const Eigen::SparseMatrix<double>& lower);

}  // namespace freeform
