#include "freeform/regions/regions.h"

#include "freeform/common/error.h"

#include <algorithm>

namespace freeform {
namespace {

void check_vertex(const Mesh& mesh, Vertex v, const std::string& where) {
  if (v.idx() < 0 || v.idx() >= mesh.n_vertices())
    throw InvalidInput(where + " names vertex " + std::to_string(v.idx()) + ", but the mesh has " +
                       std::to_string(mesh.n_vertices()) + " vertices");
}

}  // namespace

Regions::Regions(const Mesh& mesh, const std::vector<Vertex>& support, std::vector<HandleRegion> handles)
    : role_(mesh.n_vertices(), Role::Fixed), handle_(mesh.n_vertices(), -1), handles_(std::move(handles)) {
  if (support.empty()) throw InvalidInput("the support region is empty: select the vertices that may move");
  for (Vertex v : support) {
    check_vertex(mesh, v, "the support");
    role_[v] = Role::Free;
  }
  for (std::size_t h = 0; h < handles_.size(); ++h) {
    auto& vs = handles_[h].vertices;
    const std::string name = "handle " + std::to_string(h);
    if (vs.empty()) throw InvalidInput(name + " has no vertices");
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    for (Vertex v : vs) {
      check_vertex(mesh, v, name);
      if (handle_[v] >= 0)
        throw InvalidInput("vertex " + std::to_string(v.idx()) + " is in handle " + std::to_string(handle_[v]) +
                           " and in " + name + "; handles must not overlap");
      handle_[v] = static_cast<int>(h);
      role_[v] = Role::Handle;
    }
    movable_index_.push_back(handles_[h].movable ? n_movable_++ : -1);
  }
  for (Vertex v : mesh.vertices()) {
    if (role_[v] == Role::Free) free_.push_back(v);
    if (role_[v] == Role::Fixed) ++n_fixed_;
  }
  if (free_.empty()) throw InvalidInput("the support has no free vertex: every support vertex is in a handle");
}

}  // namespace freeform
