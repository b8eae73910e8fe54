// The report of a precomputed edit and one of its frames: the keys `freeform deform --report`
// writes (docs/cli.md) and the Python module's solver.stats, built in one place.
#pragma once

#include "freeform/common/json_reader.h"
#include "freeform/edit/edit_solver.h"

#include <string>
#include <vector>

namespace freeform {

// deformation, order, smoothness {outer, inner, segments [{vertices, value}]}, counts {free, fixed, constrained_in_system,
// handles [{vertices, movable}]}, solver, symmetric, timings_ms {assembly, factorization,
// basis, evaluate}, residual, folded_edges (mesh/folds.h), anisotropic {requested, used, principal_extents, fallback,
// parametrization_ms}, multiresolution (null without it; else detail = "normal_displacement" or "nonlinear_model", decomposition_ms,
// smooth_operator, operator_fallback, operator_shape_ms, reconstruct_ms, normal_encoded, fallback, max_height, flipped_triangles, overlaps).
// nonlinear (null for the linear model; else iterations, residual = the last iteration's
// largest vertex move / support extent, converged, iterate_ms).
// `frame` gives the per-frame times, `problems` the frame's detail problems; `nonlinear` the
// state to report instead of the solver's (a DragSession's frame: its worker owns the model).
Json edit_report(const EditSolver& solver, const EditTimings& frame, const EditProblems& problems,
                 const NonlinearState* nonlinear = nullptr);

// What a user should be told about a precomputed edit and a frame, one sentence each: an
// inaccurate solve, degenerate or needle-thin triangles, isolated support vertices, the
// anisotropic fallback, a nonlinear run stopped at its cap, folded edges, flattened or flipped
// detail. `freeform deform` prints them, the report's "warnings" (so Python's solver.stats)
// lists them, the editor's panel shows them (with default problems and no nonlinear state: the
// precompute's only; its worker thread owns the model's state). `nonlinear`: the state whose
// cap to report (null: none).
std::vector<std::string> edit_warnings(const EditSolver& solver, const EditProblems& problems = {},
                                       const NonlinearState* nonlinear = nullptr);

}  // namespace freeform
