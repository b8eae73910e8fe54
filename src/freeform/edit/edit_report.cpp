#include "freeform/edit/edit_report.h"

#include "freeform/common/parallel.h"
#include "freeform/mesh/folds.h"

#include <fmt/format.h>

namespace freeform {

Json edit_report(const EditSolver& solver, const EditTimings& frame, const EditProblems& problems,
                 const NonlinearState* nonlinear_state) {
  const Regions& regions = solver.regions();
  const BcmSettings& settings = solver.settings();
  const BcmStats& st = solver.stats().bcm;
  const std::optional<MultiresStats>& ms = solver.stats().multires;
  Json handles = Json::array();
  for (const HandleRegion& h : regions.handles()) handles.push_back({{"vertices", h.vertices.size()}, {"movable", h.movable}});
  Json multires = nullptr;
  if (ms)
    multires = {{"detail", ms->detail_by_model || !solver.detail_carried().empty() ? "nonlinear_model"
                           : ms->vertex_frames > 0                                 ? "vertex_frames"
                                                                                   : "normal_displacement"},
                {"detail_carried", solver.detail_carried().empty() ? Json(nullptr) : Json(solver.detail_carried())},
                {"decomposition_ms", ms->decomposition_ms},
                {"smooth_operator", ms->smooth_operator},
                {"operator_fallback", ms->operator_fallback.empty() ? Json(nullptr) : Json(ms->operator_fallback)},
                {"operator_shape_ms", ms->operator_shape_ms},
                {"reconstruct_ms", frame.reconstruction_ms},
                {"normal_encoded", ms->normal_encoded},
                {"fallback", ms->fallback},
                {"vertex_frames", ms->vertex_frames},
                {"max_height", ms->max_height},
                {"flipped_triangles", problems.detail.flipped},
                {"overlaps", problems.detail.overlaps}};
  // The state given (a DragSession's frame) if the solver has a model, else the solver's own.
  const NonlinearState* ns = solver.nonlinear_state() && nonlinear_state ? nonlinear_state : solver.nonlinear_state();
  Json nonlinear = nullptr;
  if (ns)
    nonlinear = {{"iterations", ns->iterations},
                 {"residual", ns->step},
                 {"converged", ns->converged},
                 {"iterate_ms", ns->ms}};
  Json phases = Json::array();
  for (const Phase& p : solver.stats().phases)
    phases.push_back({{"name", p.name}, {"wall_ms", p.time.wall_ms}, {"cpu_ms", p.time.cpu_ms}});
  const PhaseTime& whole = solver.stats().precompute;
  Json precompute = {{"wall_ms", whole.wall_ms},
                     {"cpu_ms", whole.cpu_ms},
                     {"threads", thread_budget()},
                     {"blas_threads", blas_threads()},
                     {"phases", std::move(phases)},
                     {"analysis_ahead", {{"wall_ms", st.analysis_ahead_ms}, {"cpu_ms", st.analysis_ahead_cpu_ms}}},
                     {"ordering", st.ordering},
                     {"factor_nonzeros", st.factor_nonzeros}};
  Json segments = Json::array();
  for (const SmoothnessSegment& seg : settings.smoothness.segments)
    segments.push_back({{"vertices", seg.vertices.size()}, {"value", seg.value}});
  return {
      {"deformation", deformation_name(solver.stats().deformation)},
      {"order", settings.order},
      {"smoothness", {{"outer", resolved_outer(settings)}, {"inner", resolved_inner(settings)}, {"segments", std::move(segments)}}},
      {"counts",
       {{"free", regions.n_free()}, {"fixed", regions.n_fixed()}, {"constrained_in_system", st.constrained}, {"handles", handles},
        {"isolated_ignored", solver.stats().isolated_ignored}}},
      {"solver", st.solver},
      {"symmetric", st.symmetric},
      {"analysis_ahead", st.analysis_ahead},
      {"timings_ms",
       {{"assembly", st.assembly_ms},
        {"factorization", st.factorization_ms},
        {"basis", st.basis_ms},
        {"refinement", st.refinement_ms},
        {"analysis_ahead", st.analysis_ahead_ms},
        {"evaluate", frame.evaluate_ms}}},
      {"precompute", std::move(precompute)},
      {"residual", st.residual},
      {"forward_error", st.forward_error},
      {"refinement",
       {{"steps", st.refinement_steps}, {"converged", st.refinement_converged}, {"unrefined_error", st.unrefined_error}}},
      {"operator", {{"degenerate_faces", st.degenerate_faces}, {"clamped_cotangents", st.clamped_cotangents}}},
      {"folded_edges", problems.folded_edges},
      {"anisotropic",
       {{"requested", settings.anisotropic},
        {"used", st.anisotropic},
        {"principal_extents", {st.principal_extents[0], st.principal_extents[1]}},
        {"fallback", st.anisotropic_fallback.empty() ? Json(nullptr) : Json(st.anisotropic_fallback)},
        {"parametrization_ms", st.parametrization_ms}}},
      {"multiresolution", std::move(multires)},
      {"nonlinear", std::move(nonlinear)},
      {"warnings", edit_warnings(solver, problems, ns)},
  };
}

std::vector<std::string> edit_warnings(const EditSolver& solver, const EditProblems& problems,
                                       const NonlinearState* nonlinear) {
  std::vector<std::string> out;
  const BcmStats& st = solver.stats().bcm;
  if (!solver.stats().order_fallback.empty()) out.push_back(solver.stats().order_fallback);
  if (nonlinear && !nonlinear->converged && nonlinear->iterations > 0 && solver.nonlinear_options()) {
    const double tolerance = solver.nonlinear_options()->tolerance;
    // At the cap the result is the iterate with the smallest step, which can be within the
    // tolerance where the iteration cycles around a point no plain step confirms.
    if (nonlinear->step > tolerance)
      out.push_back(
          fmt::format("the nonlinear model stopped at its cap of {} iterations before converging (residual "
                      "{:.2g} > tolerance {:.2g}); raise \"nonlinear\": {{\"max_iterations\"}} in the edit file",
                      nonlinear->iterations, nonlinear->step, tolerance));
    else
      out.push_back(
          fmt::format("the nonlinear model stopped at its cap of {} iterations before converging: it cycled "
                      "around the result (residual {:.2g}, within the tolerance {:.2g}) without settling there",
                      nonlinear->iterations, nonlinear->step, tolerance));
  }
  if (st.forward_error > kForwardErrorWarning)
    out.push_back(fmt::format("the solve's estimated error is {:.2g} of the bounding-box diagonal (refinement: {} "
                              "steps, {}); the support is too large for an accurate order-{} solve: use a smaller "
                              "support or a lower order",
                              st.forward_error, st.refinement_steps,
                              st.refinement_converged ? "converged" : "did not converge", solver.settings().order));
  if (st.degenerate_faces > 0 || st.clamped_cotangents > 0)
    out.push_back(fmt::format("{} degenerate triangles (no stiffness) and {} clamped cotangents (needle-thin "
                              "triangles) in the support's operator",
                              st.degenerate_faces, st.clamped_cotangents));
  if (const EditStats& stats = solver.stats(); stats.open_seam_vertices > 0)
    out.push_back(
        fmt::format("{} free vertices lie on an open seam: each has the position of another boundary vertex "
                    "that the mesh does not join to it (e.g. {} and {}), so the surface may open there; "
                    "weld them in the file to deform across it",
                    stats.open_seam_vertices, stats.open_seam_example[0].idx(), stats.open_seam_example[1].idx()));
  if (solver.stats().isolated_ignored > 0)
    out.push_back(fmt::format("{} support vertices belong to no triangle (isolated): they were left where they are",
                              solver.stats().isolated_ignored));
  if (!st.anisotropic && !st.anisotropic_fallback.empty())
    out.push_back("anisotropic bending fell back to the isotropic operator: " + st.anisotropic_fallback);
  if (problems.folded_edges > 0)
    out.push_back(fmt::format("{} folded edges (dihedral angle grew by more than {:g} degrees)", problems.folded_edges,
                              kFoldDegrees));
  if (problems.detail.overlaps > 0)
    out.push_back(fmt::format("the bend is tighter than the detail is tall at {} vertices: their detail was flattened "
                              "there to keep it from folding over",
                              problems.detail.overlaps));
  if (problems.detail.flipped > 0)
    out.push_back(fmt::format("{} detail triangles flipped against their base", problems.detail.flipped));
  return out;
}

}  // namespace freeform
