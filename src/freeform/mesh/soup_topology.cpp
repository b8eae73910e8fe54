#include "freeform/mesh/soup_topology.h"

#include <algorithm>
#include <numeric>

namespace freeform::detail {
namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

int corner_from(int d) { return d; }
int corner_to(int d) { return d - d % 3 + (d % 3 + 1) % 3; }

}  // namespace

SoupTopology analyze_soup(int n_vertices, const std::vector<Tri>& faces) {
  const int n_directed = static_cast<int>(faces.size()) * 3;
  auto from = [&](int d) { return faces[d / 3][d % 3]; };
  auto to = [&](int d) { return faces[d / 3][(d % 3 + 1) % 3]; };

  // Bucket directed edges by their smaller endpoint (counting sort), then group by the larger.
  std::vector<int> start(static_cast<std::size_t>(n_vertices) + 1, 0);
  for (int d = 0; d < n_directed; ++d) ++start[std::min(from(d), to(d)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> bucket(n_directed);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int d = 0; d < n_directed; ++d) bucket[fill[std::min(from(d), to(d))]++] = d;
  }

  SoupTopology topo;
  topo.twin.assign(n_directed, -1);
  UnionFind corners(n_directed);
  for (int v = 0; v < n_vertices; ++v) {
    auto first = bucket.begin() + start[v];
    auto last = bucket.begin() + start[v + 1];
    std::sort(first, last, [&](int a, int b) {
      const int ka = std::max(from(a), to(a)), kb = std::max(from(b), to(b));
      return ka != kb ? ka < kb : a < b;
    });
    for (auto it = first; it != last;) {
      const int other = std::max(from(*it), to(*it));
      auto group_end = std::find_if(it, last, [&](int d) { return std::max(from(d), to(d)) != other; });
      const auto count = group_end - it;
      if (count == 2) {
        const int a = *it, b = *(it + 1);
        if (from(a) == to(b)) {
          topo.twin[a] = b;
          topo.twin[b] = a;
          corners.unite(corner_from(a), corner_to(b));
          corners.unite(corner_to(a), corner_from(b));
        } else {
          topo.inconsistent_edges.push_back({v, other});
        }
      } else if (count > 2) {
        topo.nonmanifold_edges.push_back({v, other});
      }
      it = group_end;
    }
  }

  // Number the fans of each vertex in order of their first corner.
  topo.fan.assign(n_directed, -1);
  topo.fan_count.assign(n_vertices, 0);
  std::vector<int> root_fan(n_directed, -1);
  for (int c = 0; c < n_directed; ++c) {
    const int root = corners.find(c);
    if (root_fan[root] < 0) root_fan[root] = topo.fan_count[from(c)]++;
    topo.fan[c] = root_fan[root];
  }
  return topo;
}

}  // namespace freeform::detail
