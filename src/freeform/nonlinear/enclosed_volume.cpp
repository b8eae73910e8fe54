#include "freeform/nonlinear/enclosed_volume.h"

#include "freeform/common/parallel.h"
#include "freeform/mesh/traversal.h"
#include "freeform/numerics/cubic.h"

#include <algorithm>
#include <cmath>

namespace freeform {
namespace {

// The largest move of a volume correction, in multiples of the even offset that restores the
// volume (EnclosedVolumes::multiplier).
constexpr double kVolumeEfficiency = 16.0;

// Face sums run over fixed chunks of faces, in parallel, and add the chunks' sums in order: the
// same bits on any number of threads.
constexpr std::size_t kFaceChunk = 4096;

// merge(total, chunk_sum) over the chunks' sums in order; each chunk's from term(face, sum).
template <std::size_t N, class Term, class Merge>
std::array<double, N> chunked_sum(std::size_t faces, const Term& term, const Merge& merge) {
  const std::size_t chunks = (faces + kFaceChunk - 1) / kFaceChunk;
  std::vector<std::array<double, N>> sums(chunks, std::array<double, N>{});
  parallel_for(static_cast<std::ptrdiff_t>(chunks), 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto c = static_cast<std::size_t>(lo); c < static_cast<std::size_t>(hi); ++c)
      for (std::size_t f = c * kFaceChunk; f < std::min(faces, (c + 1) * kFaceChunk); ++f) term(f, sums[c]);
  });
  std::array<double, N> total{};
  for (const auto& s : sums) merge(total, s);
  return total;
}

void add_sums(std::array<double, 1>& total, const std::array<double, 1>& s) { total[0] += s[0]; }

}  // namespace

// Who moves in which volume. Support parts that share a handle keep one volume together (the
// handle's motion belongs to both, so neither alone restores what it changed); each other part
// keeps its own. A free vertex moves in its group's volume, a handle's vertices in the group its
// rows lie in, or in every group's where they lie in none.
struct EnclosedVolumes::Roles {
  VertexData<int> group;          // free vertices: their group of support parts; others -1
  VertexData<int> owner;          // handle vertices: their movable handle; others -1
  std::vector<int> handle_group;  // per movable handle: its group, or -1 (every group's)

  Roles(const Mesh& mesh, const VertexData<int>& local, int n_free, const Regions& regions,
        std::span<const int> part_of_row)
      : group(static_cast<std::size_t>(mesh.n_vertices()), -1),
        owner(static_cast<std::size_t>(mesh.n_vertices()), -1),
        handle_group(static_cast<std::size_t>(regions.n_movable()), -1) {
    const auto part_of = [&](int row) {
      return row >= 0 && row < static_cast<int>(part_of_row.size()) ? part_of_row[static_cast<std::size_t>(row)] : 0;
    };
    // Union-find over the parts, joined through the handles their rows reach.
    std::vector<int> root(
        part_of_row.empty() ? 1
                            : static_cast<std::size_t>(*std::max_element(part_of_row.begin(), part_of_row.end()) + 1));
    for (std::size_t i = 0; i < root.size(); ++i) root[i] = static_cast<int>(i);
    const auto find = [&root](int a) {
      while (root[static_cast<std::size_t>(a)] != a)
        a = root[static_cast<std::size_t>(a)] = root[static_cast<std::size_t>(root[static_cast<std::size_t>(a)])];
      return a;
    };
    for (Vertex v : mesh.vertices()) {
      const int row = local[v], h = regions.handle_of(v);
      owner[v] = h >= 0 ? regions.movable_index(h) : -1;
      if (owner[v] < 0 || row < n_free || row >= static_cast<int>(part_of_row.size())) continue;
      int& hg = handle_group[static_cast<std::size_t>(owner[v])];
      if (hg < 0)
        hg = part_of(row);
      else
        root[static_cast<std::size_t>(find(hg))] = find(part_of(row));
    }
    for (int& hg : handle_group)
      if (hg >= 0) hg = find(hg);
    for (Vertex v : mesh.vertices())
      if (local[v] >= 0 && local[v] < n_free) group[v] = find(part_of(local[v]));
  }
  // Vertex v stays at its rest in group g's volume.
  bool at_rest(Vertex v, int g) const {
    if (group[v] >= 0) return group[v] != g;
    const int m = owner[v];
    return m >= 0 && handle_group[static_cast<std::size_t>(m)] >= 0 && handle_group[static_cast<std::size_t>(m)] != g;
  }
};

EnclosedVolumes::EnclosedVolumes(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<int>& local,
                                 int n_free, const Regions& regions, std::span<const int> part_of_row)
    : n_free_(n_free) {
  const Components comp = connected_components(mesh);
  std::vector<char> closed(static_cast<std::size_t>(comp.count), 1), has_free(static_cast<std::size_t>(comp.count), 0);
  for (Halfedge h : mesh.halfedges())
    if (mesh.is_boundary(h)) closed[static_cast<std::size_t>(comp.vertex_component[mesh.to_vertex(h)])] = 0;
  for (Vertex v : mesh.vertices())
    if (local[v] >= 0 && local[v] < n_free) has_free[static_cast<std::size_t>(comp.vertex_component[v])] = 1;
  std::vector<int> kept(static_cast<std::size_t>(comp.count), -1);
  std::vector<std::vector<Vertex>> vertices;
  std::vector<std::vector<Face>> faces;
  for (int c = 0; c < comp.count; ++c)
    if (closed[static_cast<std::size_t>(c)] && has_free[static_cast<std::size_t>(c)]) {
      kept[static_cast<std::size_t>(c)] = static_cast<int>(vertices.size());
      vertices.emplace_back();
      faces.emplace_back();
    }
  if (vertices.empty()) return;
  for (Vertex v : mesh.vertices())
    if (const int k = kept[static_cast<std::size_t>(comp.vertex_component[v])]; k >= 0 && !mesh.is_isolated(v))
      vertices[static_cast<std::size_t>(k)].push_back(v);
  for (Face f : mesh.faces())
    if (const int k = kept[static_cast<std::size_t>(comp.face_component[f])]; k >= 0)
      faces[static_cast<std::size_t>(k)].push_back(f);
  const Roles roles(mesh, local, n_free, regions, part_of_row);
  VertexData<int> extra_index(static_cast<std::size_t>(mesh.n_vertices()), -1);
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    std::vector<int> groups;
    for (Vertex v : vertices[k])
      if (roles.group[v] >= 0) groups.push_back(roles.group[v]);
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    for (int g : groups) add_part(mesh, rest, local, roles, g, vertices[k], faces[k], extra_index);
  }
  // The rest volume from the rest rows, by the same code as every frame's (exact at identity).
  Eigen::Index rows = 0;
  for (Vertex v : mesh.vertices()) rows = std::max<Eigen::Index>(rows, local[v] + 1);
  RowMatrixX3d x = RowMatrixX3d::Zero(rows, 3);
  for (Vertex v : mesh.vertices())
    if (local[v] >= 0) x.row(local[v]) = rest[v].transpose();
  for (Part& part : parts_) {
    part.fixed_sum = fixed_sum(part, x);
    part.rest_volume = part.target = (part.fixed_sum + moving_sum(part, x)) / 6.0;
  }
}

void EnclosedVolumes::add_part(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<int>& local,
                               const Roles& roles, int group, const std::vector<Vertex>& vertices,
                               const std::vector<Face>& faces, VertexData<int>& extra_index) {
  Part& part = parts_.emplace_back();
  for (Vertex v : vertices) {
    const bool at_rest = roles.at_rest(v, group);
    if (local[v] >= 0 && !at_rest) {
      part.local_rows.push_back(local[v]);
    } else {
      extra_index[v] = static_cast<int>(part.extra.size());
      part.extra.push_back(v);
      part.extra_owner.push_back(at_rest ? -1 : roles.owner[v]);
      part.extra_rest.push_back(rest[v]);
    }
    part.centre += rest[v];
  }
  part.centre /= static_cast<double>(vertices.size());
  for (Face f : faces) {
    std::array<int, 3> corners{};
    const std::array<Vertex, 3> vs = mesh.vertices(f);
    bool moves = false;
    for (std::size_t k = 0; k < 3; ++k) {
      const int row = local[vs[k]];
      corners[k] = row >= 0 && !roles.at_rest(vs[k], group) ? row : -1 - extra_index[vs[k]];
      moves = moves || (corners[k] >= 0 && corners[k] < n_free_);
    }
    (moves ? part.moving : part.fixed).push_back(corners);
  }
  part.extra_now = part.extra_rest;
  index_free_corners(part);
  double extent = 0.0;
  for (Vertex v : vertices) extent = std::max(extent, (rest[v] - part.centre).cwiseAbs().maxCoeff());
  int e = 0;
  std::frexp(extent > 0.0 && std::isfinite(extent) ? extent : 1.0, &e);
  part.scale = std::ldexp(1.0, e);
  part.inv_scale = std::ldexp(1.0, -e);
  scale_extras(part);
  for (Vertex v : part.extra) extra_index[v] = -1;
}

void EnclosedVolumes::index_free_corners(Part& part) const {
  for (int r : part.local_rows)
    if (r < n_free_) part.free_rows.push_back(r);
  std::sort(part.free_rows.begin(), part.free_rows.end());
  const auto slot = [&](int r) {
    return static_cast<std::size_t>(std::lower_bound(part.free_rows.begin(), part.free_rows.end(), r) -
                                    part.free_rows.begin());
  };
  part.corner_offset.assign(part.free_rows.size() + 1, 0);
  for (const auto& f : part.moving)
    for (int r : f)
      if (r >= 0 && r < n_free_) ++part.corner_offset[slot(r) + 1];
  for (std::size_t i = 0; i < part.free_rows.size(); ++i) part.corner_offset[i + 1] += part.corner_offset[i];
  part.opposite.resize(2 * static_cast<std::size_t>(part.corner_offset.back()));
  std::vector<int> next(part.corner_offset.begin(), part.corner_offset.end() - 1);
  for (const auto& f : part.moving)  // in face order: the serial sum's order
    for (std::size_t k = 0; k < 3; ++k) {
      const int r = f[k];
      if (r < 0 || r >= n_free_) continue;
      const auto at = 2 * static_cast<std::size_t>(next[slot(r)]++);
      part.opposite[at] = f[(k + 1) % 3];
      part.opposite[at + 1] = f[(k + 2) % 3];
    }
}

void EnclosedVolumes::scale_extras(Part& part) {
  part.extra_scaled.resize(part.extra_now.size());
  for (std::size_t i = 0; i < part.extra_now.size(); ++i)
    part.extra_scaled[i] = (part.extra_now[i] - part.centre) * part.inv_scale;
}

void EnclosedVolumes::scale_corners(const Part& part, const RowMatrixX3d& x) const {
  scaled_.resize(static_cast<std::size_t>(x.rows()));
  for (int r : part.local_rows) scaled_[static_cast<std::size_t>(r)] = corner(part, r, x);
}

Vec3 EnclosedVolumes::corner(const Part& part, int index, const RowMatrixX3d& x) const {
  return ((index >= 0 ? Vec3(x.row(index).transpose()) : part.extra_now[static_cast<std::size_t>(-1 - index)]) -
          part.centre) *
         part.inv_scale;
}

void EnclosedVolumes::start(std::span<const Eigen::Affine3d> transforms, const RowMatrixX3d& x,
                            const RowMatrixX3d* dragged, std::span<const Eigen::Affine3d> moves) {
  for (Part& part : parts_) {
    // Without drags or scalings the target is the rest volume to the bit, so the rest stays a
    // fixed point.
    part.target = part.rest_volume;
    if (dragged) {
      for (std::size_t i = 0; i < part.extra.size(); ++i) {
        const int m = part.extra_owner[i];
        part.extra_now[i] = m >= 0 ? Vec3(moves[static_cast<std::size_t>(m)] * part.extra_rest[i]) : part.extra_rest[i];
      }
      scale_extras(part);
      part.target = (fixed_sum(part, *dragged) + moving_sum(part, *dragged)) / 6.0;
    }
    for (std::size_t i = 0; i < part.extra.size(); ++i) {
      const int m = part.extra_owner[i];
      part.extra_now[i] =
          m >= 0 ? Vec3(transforms[static_cast<std::size_t>(m)] * part.extra_rest[i]) : part.extra_rest[i];
    }
    scale_extras(part);
    part.fixed_sum = fixed_sum(part, x);
  }
}

double EnclosedVolumes::fixed_sum(const Part& part, const RowMatrixX3d& x) const {
  double v = 0.0;
  for (const auto& f : part.fixed) v += corner(part, f[0], x).dot(corner(part, f[1], x).cross(corner(part, f[2], x)));
  return v;
}

double EnclosedVolumes::moving_sum(const Part& part, const RowMatrixX3d& x) const {
  const auto term = [&](std::size_t i, std::array<double, 1>& sum) {
    const auto& f = part.moving[i];
    sum[0] += corner(part, f[0], x).dot(corner(part, f[1], x).cross(corner(part, f[2], x)));
  };
  return chunked_sum<1>(part.moving.size(), term, add_sums)[0];
}

double EnclosedVolumes::volume(int c, const RowMatrixX3d& x) const {
  const Part& part = parts_[static_cast<std::size_t>(c)];
  return (part.fixed_sum + moving_sum(part, x)) / 6.0;
}

void EnclosedVolumes::gradient(int c, const RowMatrixX3d& x, Eigen::Ref<Eigen::MatrixXd> g) const {
  // Per free row, the sum over its faces of the cross product of the face's other two corners
  // (d/dy of V / scale^3, y = x / scale), in face order.
  const Part& part = parts_[static_cast<std::size_t>(c)];
  g.setZero();
  scale_corners(part, x);
  const auto rows = static_cast<std::ptrdiff_t>(part.free_rows.size());
  parallel_for(rows, 1024, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<std::size_t>(lo); i < static_cast<std::size_t>(hi); ++i) {
      Vec3 sum = Vec3::Zero();
      for (auto e = 2 * static_cast<std::size_t>(part.corner_offset[i]);
           e < 2 * static_cast<std::size_t>(part.corner_offset[i + 1]); e += 2)
        sum += scaled(part, part.opposite[e]).cross(scaled(part, part.opposite[e + 1])) / 6.0;
      g.row(part.free_rows[i]) = sum.transpose();
    }
  });
}

double EnclosedVolumes::multiplier(int c, const RowMatrixX3d& x, const Eigen::MatrixXd& u) const {
  // The volume at x + lambda u is a cubic in lambda: its coefficients summed over the faces,
  // then the root nearest to 0. (Newton from 0 with a fixed tolerance skipped the correction
  // for dozens of iterations of a 35k-vertex twist on the bunny, then jumped to a far root
  // that moved vertices by 1.7 times the support's extent.)
  const Part& part = parts_[static_cast<std::size_t>(c)];
  scale_corners(part, x);
  scaled_u_.resize(static_cast<std::size_t>(u.rows()));
  for (int r : part.free_rows) scaled_u_[static_cast<std::size_t>(r)] = u.row(r).transpose() * part.inv_scale;
  auto du = [&](int index) {
    return index >= 0 && index < n_free_ ? scaled_u_[static_cast<std::size_t>(index)] : Vec3::Zero();
  };
  // k[0..3], the area of the moving faces, the largest |u|^2 of a corner.
  const auto term = [&](std::size_t i, std::array<double, 6>& sum) {
    const auto& f = part.moving[i];
    const Vec3 &a = scaled(part, f[0]), &b = scaled(part, f[1]), &d = scaled(part, f[2]);
    const Vec3 ua = du(f[0]), ub = du(f[1]), ud = du(f[2]);
    sum[0] += a.dot(b.cross(d));
    sum[1] += ua.dot(b.cross(d)) + a.dot(ub.cross(d)) + a.dot(b.cross(ud));
    sum[2] += ua.dot(ub.cross(d)) + ua.dot(b.cross(ud)) + a.dot(ub.cross(ud));
    sum[3] += ua.dot(ub.cross(ud));
    sum[4] += 0.5 * (b - a).cross(d - a).norm();
    sum[5] = std::max({sum[5], ua.squaredNorm(), ub.squaredNorm(), ud.squaredNorm()});
  };
  const auto merge = [](std::array<double, 6>& total, const std::array<double, 6>& s) {
    for (std::size_t j = 0; j < 5; ++j) total[j] += s[j];
    total[5] = std::max(total[5], s[5]);
  };
  const std::array<double, 6> k = chunked_sum<6>(part.moving.size(), term, merge);
  const double area = k[4], u_max = std::sqrt(k[5]);
  const double deficit = (part.fixed_sum + k[0]) / 6.0 - part.target;  // as volume(): exactly 0 at the rest
  if (deficit == 0.0 || !(u_max > 0.0) || !std::isfinite(u_max)) return 0.0;
  // No correction moves a vertex by more than the component's extent (~1 in these
  // coordinates), nor by more than kVolumeEfficiency times the even offset of the moving
  // faces that would restore the volume (|deficit| / area): beyond that, u does not inflate
  // the component but stretches its soft parts (a head turned 90 degrees, its volume within
  // 0.3 %, moved its thin ears by up to 0.38 of the extent, 40-840 times that offset; the
  // survey's bar, capsule and cactus need 1.6-5.2 times). Beyond it the volume is left as it is.
  const double reach = std::min(1.0, kVolumeEfficiency * std::abs(deficit) / area) / u_max;
  double roots[3];
  const int n = cubic_roots(deficit, k[1] / 6.0, k[2] / 6.0, k[3] / 6.0, reach, roots);
  double best = 0.0;
  bool found = false;
  for (int i = 0; i < n; ++i)
    if (std::abs(roots[i]) <= reach && (!found || std::abs(roots[i]) < std::abs(best))) {
      best = roots[i];
      found = true;
    }
  return found ? best : 0.0;
}

}  // namespace freeform
