// The report of a precomputed edit and one of its frames: the keys `freeform deform --report`
// writes (docs/cli.md) and the Python module's solver.stats, built in one place.
#pragma once

#include "freeform/common/json_reader.h"
#include "freeform/edit/edit_solver.h"

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

}  // namespace freeform
