#include "freeform/bcm/patch.h"

namespace freeform {

Patch build_patch(const Mesh& mesh, const std::vector<Vertex>& free, int k) {
  Patch p;
  p.local = VertexData<int>(static_cast<std::size_t>(mesh.n_vertices()), -1);
  p.n_free = static_cast<int>(free.size());
  p.order = free;
  p.dist.assign(free.size(), 0);
  for (int i = 0; i < p.n_free; ++i) p.local[free[static_cast<std::size_t>(i)]] = i;
  std::size_t begin = 0;
  p.n_inner = k == 1 ? p.n_free : -1;
  for (int d = 1; d <= k; ++d) {
    const std::size_t end = p.order.size();
    for (std::size_t i = begin; i < end; ++i) {
      for (Halfedge h : mesh.outgoing(p.order[i])) {
        const Vertex w = mesh.to_vertex(h);
        if (p.local[w] >= 0) continue;
        p.local[w] = static_cast<int>(p.order.size());
        p.order.push_back(w);
        p.dist.push_back(d);
      }
    }
    if (d == k - 1) p.n_inner = static_cast<int>(p.order.size());
    begin = end;
  }
  return p;
}

}  // namespace freeform
