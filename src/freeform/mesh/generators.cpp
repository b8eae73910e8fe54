// Generated test and demo meshes (see generators.h). Every generator validates its arguments
// (InvalidInput) and emits counter-clockwise faces: +z normals for the planar ones, outward
// normals for the sphere and the cylinder.
#include "freeform/mesh/generators.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

namespace freeform {
namespace {

constexpr double kPi = std::numbers::pi;

// Generated meshes stay well inside int indexing (faces count 2 * cells).
constexpr long long kMaxElements = 200'000'000LL;

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidInput(message);
}

void require_positive(double value, const char* what, const char* function) {
  require(std::isfinite(value) && value > 0.0,
          std::string(function) + ": " + what + " must be finite and > 0 (got " + std::to_string(value) + ")");
}

void require_count(int value, int minimum, const char* what, const char* function) {
  require(value >= minimum, std::string(function) + ": " + what + " must be >= " + std::to_string(minimum) + " (got " +
                                std::to_string(value) + ")");
}

void require_size(long long elements, const char* function) {
  require(elements <= kMaxElements, std::string(function) + ": resolution too large (" + std::to_string(elements) +
                                        " elements; at most " + std::to_string(kMaxElements) + ")");
}

// Grid of (nu+1) x (nv+1) vertices indexed row-major (index = j * (nu+1) + i); each cell split
// along alternating diagonals; faces counter-clockwise in (u, v). If `wrap_u`, column nu is
// column 0 (only nu columns of vertices exist).
void grid_faces(int nu, int nv, bool wrap_u, std::vector<Tri>& faces) {
  const int row = wrap_u ? nu : nu + 1;
  faces.reserve(faces.size() + 2 * static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv));
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const int i1 = wrap_u ? (i + 1) % nu : i + 1;
      const int v00 = j * row + i;
      const int v10 = j * row + i1;
      const int v01 = (j + 1) * row + i;
      const int v11 = (j + 1) * row + i1;
      if ((i + j) % 2 == 0) {  // diagonal v00 - v11
        faces.push_back({v00, v10, v11});
        faces.push_back({v00, v11, v01});
      } else {  // diagonal v10 - v01
        faces.push_back({v00, v10, v01});
        faces.push_back({v10, v11, v01});
      }
    }
  }
}

// Faces between two concentric circles of `n` vertices each (counter-clockwise order), the
// outer one rotated by half a step: +offset (outer j between inner j and j+1) or -offset
// (inner j between outer j and j+1). Normals +z for circles in the xy plane.
void staggered_band(int inner0, int outer0, int n, bool outer_ahead, std::vector<Tri>& faces) {
  for (int j = 0; j < n; ++j) {
    const int jn = (j + 1) % n;
    const int in_j = inner0 + j;
    const int in_n = inner0 + jn;
    const int out_j = outer0 + j;
    const int out_n = outer0 + jn;
    if (outer_ahead) {
      faces.push_back({in_j, out_j, in_n});
      faces.push_back({out_j, out_n, in_n});
    } else {
      faces.push_back({out_j, out_n, in_j});
      faces.push_back({in_j, out_n, in_n});
    }
  }
}

}  // namespace

TriangleSoup make_plane(int nx, int ny, double width, double height) {
  const char* fn = "make_plane";
  require_count(nx, 1, "nx", fn);
  require_count(ny, 1, "ny", fn);
  require_positive(width, "width", fn);
  require_positive(height, "height", fn);
  require_size(2LL * nx * ny + (nx + 1LL) * (ny + 1LL), fn);

  TriangleSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(nx + 1) * static_cast<std::size_t>(ny + 1));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      soup.positions.emplace_back(width * i / nx, height * j / ny, 0.0);
    }
  }
  grid_faces(nx, ny, false, soup.faces);
  return soup;
}

TriangleSoup make_disk(int rings, double radius) {
  const char* fn = "make_disk";
  require_count(rings, 1, "rings", fn);
  require_positive(radius, "radius", fn);
  require_size(9LL * rings * rings + 3LL * rings + 1, fn);

  // Ring r (1..rings) has 6r vertices starting at index 1 + 3r(r-1), at radius r/rings and
  // uniformly spaced angles; the hexagonal-lattice connectivity makes near-equilateral faces.
  auto first = [](int r) { return r == 0 ? 0 : 1 + 3 * r * (r - 1); };
  TriangleSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(first(rings + 1)));
  soup.positions.emplace_back(0.0, 0.0, 0.0);
  for (int r = 1; r <= rings; ++r) {
    const double rho = radius * r / rings;
    const int n = 6 * r;
    for (int k = 0; k < n; ++k) {
      const double phi = 2.0 * kPi * k / n;
      soup.positions.emplace_back(rho * std::cos(phi), rho * std::sin(phi), 0.0);
    }
  }

  soup.faces.reserve(6 * static_cast<std::size_t>(rings) * static_cast<std::size_t>(rings));
  for (int k = 0; k < 6; ++k) soup.faces.push_back({0, 1 + k, 1 + (k + 1) % 6});
  for (int r = 2; r <= rings; ++r) {
    const int n_in = 6 * (r - 1);
    const int n_out = 6 * r;
    auto in = [&](int s, int t) { return first(r - 1) + (s * (r - 1) + t) % n_in; };
    auto out = [&](int s, int t) { return first(r) + (s * r + t) % n_out; };
    for (int s = 0; s < 6; ++s) {
      for (int t = 0; t < r; ++t) soup.faces.push_back({out(s, t), out(s, t + 1), in(s, t)});
      for (int t = 0; t + 1 < r; ++t) soup.faces.push_back({in(s, t), out(s, t + 1), in(s, t + 1)});
    }
  }
  return soup;
}

TriangleSoup make_annulus(double r_inner, double r_outer, int rings, int segments) {
  const char* fn = "make_annulus";
  require_positive(r_inner, "r_inner", fn);
  require_positive(r_outer, "r_outer", fn);
  require(r_inner < r_outer, "make_annulus: r_inner must be < r_outer (got " + std::to_string(r_inner) + " and " +
                                 std::to_string(r_outer) + ")");
  require_count(rings, 1, "rings", fn);
  require_count(segments, 3, "segments", fn);
  require_size(3LL * rings * segments + segments, fn);

  // Circle k has radius r_inner * q^k with q = (r_outer / r_inner)^(1/rings) and is rotated by
  // half a step on odd k (staggered rows give near-equilateral faces when q ~ 1 + sqrt(3) pi / n).
  const double log_ratio = std::log(r_outer / r_inner);
  TriangleSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(rings + 1) * static_cast<std::size_t>(segments));
  for (int k = 0; k <= rings; ++k) {
    const double rho = k == 0 ? r_inner : (k == rings ? r_outer : r_inner * std::exp(log_ratio * k / rings));
    const double shift = (k % 2 == 1) ? 0.5 : 0.0;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * kPi * (j + shift) / segments;
      soup.positions.emplace_back(rho * std::cos(phi), rho * std::sin(phi), 0.0);
    }
  }
  soup.faces.reserve(2 * static_cast<std::size_t>(rings) * static_cast<std::size_t>(segments));
  for (int k = 0; k < rings; ++k) {
    staggered_band(k * segments, (k + 1) * segments, segments, k % 2 == 0, soup.faces);
  }
  return soup;
}

TriangleSoup make_icosphere(int subdivisions, double radius) {
  const char* fn = "make_icosphere";
  require_count(subdivisions, 0, "subdivisions", fn);
  require(subdivisions <= 10, "make_icosphere: subdivisions must be <= 10 (got " + std::to_string(subdivisions) + ")");
  require_positive(radius, "radius", fn);

  // Regular icosahedron: the 12 cyclic permutations of (0, +-1, +-phi), faces outward.
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, phi, 0},  {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi},  {0, 1, phi},
                         {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1},  {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  std::vector<Tri> f = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& v : p) v.normalize();

  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = midpoint.try_emplace({key.first, key.second}, static_cast<int>(p.size()));
      if (inserted) p.push_back((p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)]).normalized());
      return it->second;
    };
    std::vector<Tri> refined;
    refined.reserve(4 * f.size());
    for (const Tri& t : f) {
      const int ab = mid(t[0], t[1]);
      const int bc = mid(t[1], t[2]);
      const int ca = mid(t[2], t[0]);
      refined.push_back({t[0], ab, ca});
      refined.push_back({t[1], bc, ab});
      refined.push_back({t[2], ca, bc});
      refined.push_back({ab, bc, ca});
    }
    f = std::move(refined);
  }

  TriangleSoup soup;
  soup.positions.reserve(p.size());
  for (const Vec3& v : p) soup.positions.push_back(radius * v);
  soup.faces = std::move(f);
  return soup;
}

TriangleSoup make_cylinder(int rings, int segments, double radius, double height) {
  const char* fn = "make_cylinder";
  require_count(rings, 1, "rings", fn);
  require_count(segments, 3, "segments", fn);
  require_positive(radius, "radius", fn);
  require_positive(height, "height", fn);
  require_size(3LL * rings * segments + segments, fn);

  // Circle k at z = height * k / rings. In the unrolled (angle, z) chart the faces are
  // counter-clockwise, and e_angle x e_z = e_radial, so the normals point outward.
  TriangleSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(rings + 1) * static_cast<std::size_t>(segments));
  for (int k = 0; k <= rings; ++k) {
    const double z = height * k / rings;
    for (int j = 0; j < segments; ++j) {
      const double a = 2.0 * kPi * j / segments;
      soup.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
  }
  grid_faces(segments, rings, true, soup.faces);
  return soup;
}

TriangleSoup make_bumpy_plane(int nx, int ny, double amplitude, double frequency, double width, double height) {
  require(std::isfinite(amplitude), "make_bumpy_plane: amplitude must be finite");
  require(std::isfinite(frequency) && frequency >= 0.0,
          "make_bumpy_plane: frequency must be finite and >= 0 (got " + std::to_string(frequency) + ")");
  TriangleSoup soup = make_plane(nx, ny, width, height);
  for (Vec3& v : soup.positions) {
    v.z() =
        amplitude * std::sin(2.0 * kPi * frequency * v.x() / width) * std::sin(2.0 * kPi * frequency * v.y() / height);
  }
  return soup;
}

TriangleSoup subdivide_midpoint(const TriangleSoup& in) {
  TriangleSoup out;
  out.positions = in.positions;
  out.faces.reserve(in.faces.size() * 4);
  std::unordered_map<std::uint64_t, int> midpoint;
  midpoint.reserve(in.faces.size() * 2);
  auto mid = [&](int a, int b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
    auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(out.positions.size()));
    if (inserted) out.positions.push_back(0.5 * (in.positions[static_cast<std::size_t>(a)] + in.positions[static_cast<std::size_t>(b)]));
    return it->second;
  };
  for (const Tri& t : in.faces) {
    const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
    out.faces.push_back({t[0], ab, ca});
    out.faces.push_back({t[1], bc, ab});
    out.faces.push_back({t[2], ca, bc});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

}  // namespace freeform
