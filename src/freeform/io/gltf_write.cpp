// A new glTF 2.0 asset from a soup: one scene, node, mesh and triangle primitive, its buffer
// embedded (the BIN chunk of a .glb, a base64 data: URI in a .gltf). A glTF vertex is a
// distinct (vertex, texture coordinate row, normal row) of the corners, so seams stay split.
#include "freeform/common/error.h"
#include "freeform/common/json_reader.h"
#include "freeform/io/gltf_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace freeform {
namespace {


struct CornerKey {
  int vertex, uv, normal;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    std::uint64_t h = static_cast<std::uint32_t>(k.vertex);
    h = h * 0x9e3779b97f4a7c15ull + static_cast<std::uint32_t>(k.uv);
    h = h * 0x9e3779b97f4a7c15ull + static_cast<std::uint32_t>(k.normal);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

bool indexes_polygons(const CornerAttribute& c, int width, const MeshAttributes& a) {
  return !c.empty() && c.width == width && c.index.size() == a.polygons.corners.size() &&
         c.values.size() % static_cast<std::size_t>(width) == 0;
}

// The corner rows of each triangle corner (-1: none), found through triangle_polygon.
struct CornerRows {
  bool uv = false, normal = false;
  std::vector<std::array<int, 2>> rows;  // per face corner: uv row, normal row
};

CornerRows corner_rows(const TriangleSoup& soup, const MeshAttributes& a, std::vector<std::string>& dropped) {
  const Polygons& poly = a.polygons;
  const bool polygons = poly.size() > 0 && a.triangle_polygon.size() == soup.faces.size() &&
                        static_cast<std::size_t>(poly.offsets.back()) == poly.corners.size();
  CornerRows out;
  out.uv = polygons && indexes_polygons(a.uv, 2, a);
  out.normal = polygons && indexes_polygons(a.normal, 3, a);
  if (!a.uv.empty() && !out.uv) dropped.push_back("texture coordinates (they do not index the polygons)");
  if (!a.normal.empty() && !out.normal) dropped.push_back("normals (they do not index the polygons)");
  out.rows.assign(soup.faces.size() * 3, {-1, -1});
  if (!out.uv && !out.normal) return out;
  const auto row = [](const CornerAttribute& c, int corner) {
    const int r = c.index[static_cast<std::size_t>(corner)];
    return r >= 0 && r < c.rows() ? r : -1;
  };
  for (std::size_t t = 0; t < soup.faces.size(); ++t) {
    const int p = a.triangle_polygon[t];
    if (p < 0 || p >= poly.size()) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      for (int c = poly.offsets[static_cast<std::size_t>(p)]; c < poly.offsets[static_cast<std::size_t>(p) + 1]; ++c) {
        if (poly.corners[static_cast<std::size_t>(c)] != soup.faces[t][k]) continue;
        out.rows[t * 3 + k] = {out.uv ? row(a.uv, c) : -1, out.normal ? row(a.normal, c) : -1};
        break;
      }
    }
  }
  return out;
}

void report_dropped(const MeshAttributes& a, const NamedAttribute* color, std::vector<std::string>& dropped) {
  int split = 0;
  for (int p = 0; p < a.polygons.size(); ++p) split += a.polygons.corner_count(p) > 3 ? 1 : 0;
  if (split > 0)
    dropped.push_back(fmt::format("{} polygon{} with more than 3 corners (glTF holds triangles: triangulated)", split,
                                  split == 1 ? "" : "s"));
  for (const NamedAttribute& v : a.vertex)
    if (&v != color) dropped.push_back(fmt::format("vertex property '{}' (glTF has no custom vertex properties here)", v.name));
  for (const NamedAttribute& f : a.face)
    dropped.push_back(f.name == "color" ? std::string("face colours (glTF has no per-face values)")
                                        : fmt::format("face property '{}' (glTF has no per-face values)", f.name));
}

// Area-weighted vertex normals: for glTF vertices whose corner has no normal row.
std::vector<Vec3> vertex_normals(const TriangleSoup& soup) {
  std::vector<Vec3> n(soup.positions.size(), Vec3::Zero());
  for (const Tri& t : soup.faces) {
    const Vec3 area = (soup.positions[static_cast<std::size_t>(t[1])] - soup.positions[static_cast<std::size_t>(t[0])])
                          .cross(soup.positions[static_cast<std::size_t>(t[2])] - soup.positions[static_cast<std::size_t>(t[0])]);
    for (const int v : t) n[static_cast<std::size_t>(v)] += area;
  }
  return n;
}

// The arrays of the primitive, one entry per glTF vertex.
struct Arrays {
  std::vector<std::uint32_t> indices;
  std::vector<float> position, normal, uv, color;
};

Arrays build_arrays(const TriangleSoup& soup, const MeshAttributes& a, const CornerRows& rows, const NamedAttribute* color) {
  Arrays out;
  std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> index;
  index.reserve(soup.positions.size());
  std::vector<Vec3> fallback;
  const auto push = [](std::vector<float>& dst, const double* src, int n) {
    for (int k = 0; k < n; ++k) dst.push_back(static_cast<float>(src[k]));
  };
  for (std::size_t c = 0; c < soup.faces.size() * 3; ++c) {
    const int v = soup.faces[c / 3][c % 3];
    const CornerKey key{v, rows.rows[c][0], rows.rows[c][1]};
    const auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(index.size()));
    out.indices.push_back(it->second);
    if (!inserted) continue;
    push(out.position, soup.positions[static_cast<std::size_t>(v)].data(), 3);
    if (rows.uv) {
      const double uv[2] = {key.uv < 0 ? 0.0 : a.uv.values[2 * static_cast<std::size_t>(key.uv)],
                            key.uv < 0 ? 0.0 : 1.0 - a.uv.values[2 * static_cast<std::size_t>(key.uv) + 1]};  // v down
      push(out.uv, uv, 2);
    }
    if (rows.normal) {
      if (key.normal < 0 && fallback.empty()) fallback = vertex_normals(soup);
      Vec3 n = key.normal < 0 ? fallback[static_cast<std::size_t>(v)]
                              : Vec3(a.normal.values.data() + 3 * static_cast<std::size_t>(key.normal));
      n = n.norm() > 0 ? n.normalized() : Vec3(0, 0, 1);
      push(out.normal, n.data(), 3);
    }
    if (color) push(out.color, color->values.data() + static_cast<std::size_t>(v) * static_cast<std::size_t>(color->width), color->width);
  }
  return out;
}

class AssetBuilder {
 public:
  int add(const void* data, std::size_t bytes, int target) {
    views_.push_back({{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}, {"target", target}});
    bin_.append(static_cast<const char*>(data), bytes);
    return static_cast<int>(views_.size()) - 1;
  }
  // An accessor over `values` (float components, `width` per element), with min/max if `bounds`.
  int floats(const std::vector<float>& values, int width, bool bounds) {
    static const char* const kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
    const std::size_t count = values.size() / static_cast<std::size_t>(width);
    Json a = {{"bufferView", add(values.data(), values.size() * 4, 34962)}, {"componentType", 5126}, {"count", count},
              {"type", kTypes[width]}};
    if (bounds) {
      Json lo = Json::array(), hi = Json::array();
      for (int c = 0; c < width; ++c) {
        float l = values[static_cast<std::size_t>(c)], h = l;
        for (std::size_t i = 1; i < count; ++i) {
          l = std::min(l, values[i * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)]);
          h = std::max(h, values[i * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)]);
        }
        lo.push_back(l);
        hi.push_back(h);
      }
      a["min"] = std::move(lo);
      a["max"] = std::move(hi);
    }
    accessors_.push_back(std::move(a));
    return static_cast<int>(accessors_.size()) - 1;
  }
  int indices(const std::vector<std::uint32_t>& values) {
    accessors_.push_back({{"bufferView", add(values.data(), values.size() * 4, 34963)},
                          {"componentType", 5125},
                          {"count", values.size()},
                          {"type", "SCALAR"}});
    return static_cast<int>(accessors_.size()) - 1;
  }
  std::string finish(Json primitive, bool binary) {
    Json j = {{"asset", {{"version", "2.0"}, {"generator", "freeform"}}}, {"scene", 0}};
    Json scene = Json::object(), node = Json::object(), mesh = Json::object();
    scene["nodes"] = Json::array({0});
    node["mesh"] = 0;
    mesh["primitives"] = Json::array({std::move(primitive)});
    j["scenes"] = Json::array({std::move(scene)});
    j["nodes"] = Json::array({std::move(node)});
    j["meshes"] = Json::array({std::move(mesh)});
    j["accessors"] = std::move(accessors_);
    j["bufferViews"] = std::move(views_);
    Json buffer = {{"byteLength", bin_.size()}};
    if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + gltf_detail::base64_encode(bin_);
    j["buffers"] = Json::array({std::move(buffer)});
    if (binary) return gltf_detail::build_glb(j.dump(), bin_, true);
    return json_text(j, 6);
  }

 private:
  std::string bin_;
  Json accessors_ = Json::array(), views_ = Json::array();
};

}  // namespace

std::string write_gltf(const TriangleSoup& soup, bool binary, const MeshAttributes& attributes,
                       std::vector<std::string>& dropped) {
  io_detail::check_soup_for_writing(soup);
  for (std::size_t v = 0; v < soup.positions.size(); ++v)
    if (!soup.positions[v].cast<float>().allFinite())
      throw InvalidInput(fmt::format("cannot write glTF: vertex {} has a coordinate beyond single precision", v));
  const NamedAttribute* color = attributes.vertex_attribute("color");
  if (color && ((color->width != 3 && color->width != 4) ||
                color->values.size() != soup.positions.size() * static_cast<std::size_t>(color->width)))
    color = nullptr;
  report_dropped(attributes, color, dropped);
  if (soup.faces.empty()) {  // a valid asset with nothing to draw
    Json j = {{"asset", {{"version", "2.0"}, {"generator", "freeform"}}}, {"scene", 0}};
    j["scenes"] = Json::array({Json::object()});
    return binary ? gltf_detail::build_glb(j.dump(), {}, false) : json_text(j, 6);
  }
  const CornerRows rows = corner_rows(soup, attributes, dropped);
  const Arrays arrays = build_arrays(soup, attributes, rows, color);
  AssetBuilder asset;
  Json primitive = {{"attributes", Json::object()}};
  primitive["indices"] = asset.indices(arrays.indices);
  primitive["attributes"]["POSITION"] = asset.floats(arrays.position, 3, true);
  if (rows.normal) primitive["attributes"]["NORMAL"] = asset.floats(arrays.normal, 3, false);
  if (rows.uv) primitive["attributes"]["TEXCOORD_0"] = asset.floats(arrays.uv, 2, false);
  if (color) primitive["attributes"]["COLOR_0"] = asset.floats(arrays.color, color->width, false);
  primitive["mode"] = 4;
  return asset.finish(std::move(primitive), binary);
}

}  // namespace freeform
