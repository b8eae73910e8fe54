// Input for the scale benchmark (issue 13; scripts/bench-scale.sh runs `freeform deform` on
// it): a libcgal-demo mesh subdivided S times (midpoint, mesh/generators.h) written as binary
// PLY, and an edit file whose support is the first N + H vertices of a breadth-first order from
// vertex 0, the first H = max(50, N / 50) of them a handle translated by 5 % of the bounding
// box's diagonal; order k, multiresolution on (the editor's default).
// Args: out_dir mesh_name subdivisions free_in_thousands k. Prints the two paths.
#include "bench_meshes.h"

#include "freeform/edit/edit_json.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/traversal.h"

#include <algorithm>
#include <cstdio>
#include <string>

using namespace freeform;

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: bench_scale out_dir mesh_name subdivisions free_in_thousands k\n");
    return 2;
  }
  const std::string dir = argv[1];
  TriangleSoup soup = read_mesh((bench::mesh_dir() / argv[2]).string()).soup;
  for (int s = std::stoi(argv[3]); s > 0; --s) soup = subdivide_midpoint(soup);
  const Mesh mesh = Mesh::from_soup(soup);
  const int n = std::stoi(argv[4]) * 1000;
  const int h = std::max(50, n / 50);
  const Vertex seed[] = {Vertex(0)};
  const std::vector<Vertex> bfs = k_ring(mesh, seed, 1 << 20);
  if (static_cast<int>(bfs.size()) <= n + h) {
    std::fprintf(stderr, "the mesh has %zu vertices reachable from vertex 0: too few for %d free\n", bfs.size(), n);
    return 1;
  }
  Vec3 lo = soup.positions.front(), hi = lo;
  for (const Vec3& p : soup.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Edit edit;
  edit.settings.order = std::stoi(argv[5]);
  edit.support.assign(bfs.begin(), bfs.begin() + n + h);
  EditHandle handle;
  handle.vertices.assign(bfs.begin(), bfs.begin() + h);
  handle.manipulator.translation = 0.05 * (hi - lo).norm() * Vec3(0.0, 0.0, 1.0);
  edit.handles.push_back(handle);
  const std::string mesh_path = dir + "/scale.ply", edit_path = dir + "/scale.json";
  write_mesh(mesh_path, soup);
  write_edit_file(edit_path, edit);
  std::printf("%s %s %d\n", mesh_path.c_str(), edit_path.c_str(), mesh.n_vertices());
}
