// Example: the library's two-tier API on a generated plane. Lifts a small central handle of a
// round support with a precomputed EditSolver and writes the result. Usage: bump_plane OUT.off
#include "freeform/common/error.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace freeform;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.off\n", argv[0]);
    return 2;
  }
  try {
    const Mesh mesh = Mesh::from_soup(make_plane(40, 40));
    Edit edit;
    edit.settings.order = 3;
    edit.handles.emplace_back();
    for (Vertex v : mesh.vertices()) {
      const double r = (mesh.position(v) - Vec3(0.5, 0.5, 0)).norm();
      if (r < 0.4) edit.support.push_back(v);
      if (r < 0.05) edit.handles[0].vertices.push_back(v);
    }
    const EditSolver solver(mesh, edit);  // all sparse work happens here, once

    VertexData<Vec3> positions = mesh.positions();
    for (int frame = 1; frame <= 10; ++frame) {  // what an editor does while the user drags
      Manipulator drag;
      drag.translation = Vec3(0, 0, 0.02 * frame);
      const Eigen::Affine3d t = drag.to_affine(solver.handle_centroid(0));
      solver.evaluate(std::span(&t, 1), positions);
    }
    TriangleSoup out = mesh.to_soup();
    out.positions = positions.raw();
    write_mesh(argv[1], out);
    const BcmStats& st = solver.stats().bcm;
    std::printf("%d free vertices, solver %s, precompute %.1f ms\n", st.free, st.solver.c_str(),
                st.assembly_ms + st.factorization_ms + st.basis_ms);
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
