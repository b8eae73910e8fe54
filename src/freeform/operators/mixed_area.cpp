// Mixed Voronoi areas (Meyer, Desbrun, Schroeder, Barr 2003) and D = diag(1 / (2 A_i)).
#include "freeform/operators/face_geometry.h"
#include "freeform/operators/operators.h"

namespace freeform {

Eigen::VectorXd mixed_voronoi_areas(const Mesh& mesh, const VertexData<Vec3>& positions, OperatorDiagnostics* diag) {
  detail::check_positions(mesh, positions, "mixed_voronoi_areas");
  const int n = mesh.n_vertices();
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
  int degenerate = 0;
  double total_area = 0.0;
  double total_sq_len = 0.0;
  for (Face f : mesh.faces()) {
    const detail::FaceCorners c = detail::face_corners(mesh, f);
    const detail::TriangleGeometry g =
        detail::triangle_geometry(positions[c.v[0]], positions[c.v[1]], positions[c.v[2]]);
    total_sq_len += g.sq_len[0] + g.sq_len[1] + g.sq_len[2];
    const detail::CornerWeights w = detail::corner_weights(g);
    if (w.degenerate) {
      ++degenerate;
      continue;
    }
    for (std::size_t k = 0; k < 3; ++k) {
      area[c.v[k].idx()] += w.area[k];
      total_area += w.area[k];
    }
  }

  // Floor: 1e-12 of the mean vertex area (or of the mean squared edge length if all faces are
  // degenerate, or 1e-12 absolute if all points coincide).
  int non_isolated = 0;
  for (Vertex v : mesh.vertices()) non_isolated += mesh.is_isolated(v) ? 0 : 1;
  double reference = non_isolated > 0 ? total_area / non_isolated : 0.0;
  if (!(reference > 0.0) && mesh.n_faces() > 0) reference = total_sq_len / (3.0 * mesh.n_faces());
  if (!(reference > 0.0)) reference = 1.0;
  const double area_floor = detail::kAreaFloorRatio * reference;
  int floored = 0;
  for (Vertex v : mesh.vertices()) {
    if (!mesh.is_isolated(v) && !(area[v.idx()] >= area_floor)) {
      area[v.idx()] = area_floor;
      ++floored;
    }
  }
  if (diag) {
    diag->degenerate_faces = degenerate;
    diag->zero_area_vertices = floored;
  }
  return area;
}

Eigen::VectorXd mixed_voronoi_areas(const Mesh& mesh, OperatorDiagnostics* diag) {
  return mixed_voronoi_areas(mesh, mesh.positions(), diag);
}

Eigen::VectorXd inverse_double_areas(const Eigen::VectorXd& areas) {
  Eigen::VectorXd inv(areas.size());
  for (Eigen::Index i = 0; i < areas.size(); ++i) inv[i] = areas[i] > 0.0 ? 1.0 / (2.0 * areas[i]) : 0.0;
  return inv;
}

}  // namespace freeform
