// glTF 2.0 reader (.gltf with external or data: URI buffers, .glb): the triangles of the
// default scene in world space, welded across primitives, plus what is needed to write the
// same file back with new positions (gltf_source.h). The JSON is read with nlohmann's parser
// and checked against the core schema's types (gltf_schema.cpp); images are never opened.
#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/gltf_source.h"
#include "freeform/io/gltf_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"
#include "freeform/io/weld.h"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <optional>
#include <unordered_map>

namespace freeform {
namespace gltf_detail {
namespace {

constexpr std::uint64_t kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125, kFloat = 5126;

[[noreturn]] void fail(const std::string& path, const std::string& message) { throw IoError(path, 0, message); }

int component_bytes(std::uint64_t type) {
  switch (type) {
    case kByte:
    case kUByte:
      return 1;
    case kShort:
    case kUShort:
      return 2;
    case kUInt:
    case kFloat:
      return 4;
    default:
      return 0;
  }
}

int type_components(const std::string& type) {
  static const std::map<std::string, int, std::less<>> kTypes = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
                                                                  {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
  const auto it = kTypes.find(type);
  return it == kTypes.end() ? 0 : it->second;
}

double component(const unsigned char* p, std::uint64_t type, bool normalized) {
  switch (type) {
    case kFloat:
      return load_le<float>(p);
    case kUInt:
      return load_le<std::uint32_t>(p);
    case kUShort:
      return normalized ? load_le<std::uint16_t>(p) / 65535.0 : load_le<std::uint16_t>(p);
    case kShort:
      return normalized ? std::max(load_le<std::int16_t>(p) / 32767.0, -1.0) : load_le<std::int16_t>(p);
    case kUByte:
      return normalized ? p[0] / 255.0 : p[0];
    default:
      return normalized ? std::max(static_cast<std::int8_t>(p[0]) / 127.0, -1.0) : static_cast<std::int8_t>(p[0]);
  }
}

std::size_t array_size(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_array() ? it->size() : 0;
}

std::uint64_t uint_or(const Json& j, const char* key, std::uint64_t fallback) {
  const auto it = j.find(key);
  return it == j.end() ? fallback : it->get<std::uint64_t>();
}

struct Accessor {
  int index = 0;
  std::uint64_t component_type = kFloat;
  int components = 1;
  bool normalized = false;
  int count = 0;
  bool sparse = false;
  bool has_view = false;
};

// Buffers (loaded when first used) and accessors, every range checked before it is read.
class Accessors {
 public:
  Accessors(GltfFile& f, const std::string& path) : f_(f), path_(path) {}

  Accessor accessor(int a) const {
    const Json& j = f_.json["accessors"][static_cast<std::size_t>(a)];
    Accessor acc;
    acc.index = a;
    acc.component_type = j["componentType"].get<std::uint64_t>();
    if (component_bytes(acc.component_type) == 0)
      fail(path_, fmt::format("accessor {}: unknown componentType {}", a, acc.component_type));
    acc.components = type_components(j["type"].get<std::string>());
    if (acc.components == 0) fail(path_, fmt::format("accessor {}: unknown type {}", a, io_detail::quote(j["type"].get<std::string>())));
    const std::uint64_t count = j["count"].get<std::uint64_t>();
    if (count == 0 || count > io_detail::kMaxElements)
      fail(path_, fmt::format("accessor {}: count {} (1 to {} supported)", a, count, io_detail::kMaxElements));
    acc.count = static_cast<int>(count);
    acc.normalized = j.value("normalized", false);
    acc.sparse = j.contains("sparse");
    acc.has_view = j.contains("bufferView");
    return acc;
  }

  // A float accessor with a bufferView and no sparse part: the ones rewritten in place.
  Layout float_layout(int a, int components, const char* semantic) {
    const Accessor acc = accessor(a);
    const std::string where = fmt::format("accessor {} ({})", a, semantic);
    if (acc.component_type != kFloat || acc.components != components)
      fail(path_, fmt::format("{}: must hold float VEC{} values (componentType 5126), found componentType {} with {} "
                              "components (quantized geometry, KHR_mesh_quantization, is not supported)",
                              where, components, acc.component_type, acc.components));
    if (acc.sparse) fail(path_, fmt::format("{}: sparse accessors are not supported for {}", where, semantic));
    if (!acc.has_view) fail(path_, fmt::format("{}: has no bufferView (no data to write back)", where));
    return layout(acc, where);
  }

  // All values of an accessor (count * components), normalized integers mapped to [0, 1] or
  // [-1, 1], sparse substitutions applied, zeros where it has no bufferView.
  std::vector<double> values(const Accessor& acc, const std::string& where) {
    const auto n = static_cast<std::size_t>(acc.components);
    std::vector<double> out(static_cast<std::size_t>(acc.count) * n, 0.0);
    if (acc.has_view) {
      const Layout l = layout(acc, where);
      const auto* base = reinterpret_cast<const unsigned char*>(f_.buffers[static_cast<std::size_t>(l.buffer)].bytes.data());
      const int size = component_bytes(acc.component_type);
      for (std::size_t i = 0; i < static_cast<std::size_t>(acc.count); ++i)
        for (std::size_t c = 0; c < n; ++c)
          out[i * n + c] = component(base + l.start + i * l.stride + c * static_cast<std::size_t>(size), acc.component_type, acc.normalized);
    }
    if (acc.sparse) apply_sparse(acc, out, where);
    for (std::size_t i = 0; i < out.size(); ++i)
      if (!std::isfinite(out[i])) fail(path_, fmt::format("{}: element {} is not finite", where, i / n));
    return out;
  }

  Eigen::Vector3d vec3(const Layout& l, int i) const {
    const auto* p = reinterpret_cast<const unsigned char*>(f_.buffers[static_cast<std::size_t>(l.buffer)].bytes.data()) +
                    l.start + static_cast<std::size_t>(i) * l.stride;
    return {load_le<float>(p), load_le<float>(p + 4), load_le<float>(p + 8)};
  }

  // Loads buffer 0 from the .glb's BIN chunk.
  void set_glb_bin(std::string_view bin) {
    if (f_.buffers.empty() || f_.json["buffers"][0].contains("uri"))
      fail(path_, "the .glb has a BIN chunk but buffer 0 has a uri (the BIN chunk must be buffer 0)");
    Buffer& b = f_.buffers[0];
    b.origin = Buffer::Origin::Glb;
    b.bytes = std::string(bin);
    check_length(0);
  }

 private:
  Layout layout(const Accessor& acc, const std::string& where) {
    const Json& j = f_.json["accessors"][static_cast<std::size_t>(acc.index)];
    const auto element = static_cast<std::size_t>(acc.components * component_bytes(acc.component_type));
    Layout l = range(j["bufferView"].get<int>(), uint_or(j, "byteOffset", 0), acc.count, element, true, where);
    l.accessor = acc.index;
    return l;
  }

  // `count` elements of `element` bytes from byte `offset` of bufferView `view`: checked
  // against the view, the view against its buffer (which gets loaded).
  Layout range(int view, std::uint64_t offset, int count, std::size_t element, bool strided, const std::string& where) {
    const Json& v = f_.json["bufferViews"][static_cast<std::size_t>(view)];
    const int b = v["buffer"].get<int>();
    const std::uint64_t view_offset = uint_or(v, "byteOffset", 0), view_length = v["byteLength"].get<std::uint64_t>();
    const std::uint64_t buffer_length = f_.json["buffers"][static_cast<std::size_t>(b)]["byteLength"].get<std::uint64_t>();
    if (view_offset > buffer_length || view_length > buffer_length - view_offset)
      fail(path_, fmt::format("bufferView {} (byteOffset {}, byteLength {}) does not fit buffer {} (byteLength {})", view,
                              view_offset, view_length, b, buffer_length));
    std::uint64_t stride = element;
    if (strided && v.contains("byteStride")) {
      stride = v["byteStride"].get<std::uint64_t>();
      if (stride < element)
        fail(path_, fmt::format("{}: bufferView {} has byteStride {}, smaller than an element ({} bytes)", where, view,
                                stride, element));
    }
    const std::uint64_t need = (static_cast<std::uint64_t>(count) - 1) * stride + element;  // no overflow: count < 2^31
    if (offset > view_length || need > view_length - offset)
      fail(path_, fmt::format("{}: {} elements of {} bytes (stride {}) from byte {} need {} bytes, bufferView {} has {}",
                              where, count, element, stride, offset, need, view, view_length));
    buffer(b);
    return {-1, b, static_cast<std::size_t>(view_offset + offset), static_cast<std::size_t>(stride), count};
  }

  void apply_sparse(const Accessor& acc, std::vector<double>& out, const std::string& where) {
    const Json& s = f_.json["accessors"][static_cast<std::size_t>(acc.index)]["sparse"];
    const std::uint64_t k = s["count"].get<std::uint64_t>();
    if (k == 0 || k > static_cast<std::uint64_t>(acc.count))
      fail(path_, fmt::format("{}: sparse count {} (1 to count {})", where, k, acc.count));
    const Json& si = s["indices"];
    const std::uint64_t index_type = si["componentType"].get<std::uint64_t>();
    if (index_type != kUByte && index_type != kUShort && index_type != kUInt)
      fail(path_, fmt::format("{}: sparse indices of componentType {} (unsigned byte, short or int expected)", where, index_type));
    const int size = component_bytes(acc.component_type), isize = component_bytes(index_type);
    const Layout li = range(si["bufferView"].get<int>(), uint_or(si, "byteOffset", 0), static_cast<int>(k),
                            static_cast<std::size_t>(isize), false, where + " sparse indices");
    const Layout lv = range(s["values"]["bufferView"].get<int>(), uint_or(s["values"], "byteOffset", 0), static_cast<int>(k),
                            static_cast<std::size_t>(acc.components * size), false, where + " sparse values");
    const auto* pi = reinterpret_cast<const unsigned char*>(f_.buffers[static_cast<std::size_t>(li.buffer)].bytes.data()) + li.start;
    const auto* pv = reinterpret_cast<const unsigned char*>(f_.buffers[static_cast<std::size_t>(lv.buffer)].bytes.data()) + lv.start;
    const auto n = static_cast<std::size_t>(acc.components);
    for (std::size_t e = 0; e < k; ++e) {
      const auto i = static_cast<std::uint64_t>(component(pi + e * static_cast<std::size_t>(isize), index_type, false));
      if (i >= static_cast<std::uint64_t>(acc.count))
        fail(path_, fmt::format("{}: sparse index {} out of range (count {})", where, i, acc.count));
      for (std::size_t c = 0; c < n; ++c)
        out[i * n + c] = component(pv + (e * n + c) * static_cast<std::size_t>(size), acc.component_type, acc.normalized);
    }
  }

  const std::string& buffer(int b) {
    Buffer& buf = f_.buffers[static_cast<std::size_t>(b)];
    if (buf.loaded) return buf.bytes;
    const Json& j = f_.json["buffers"][static_cast<std::size_t>(b)];
    const std::string where = fmt::format("buffer {}", b);
    if (!j.contains("uri"))
      fail(path_, where + " has no uri (only the first buffer of a .glb, its BIN chunk, may have none)");
    const std::string uri = j["uri"].get<std::string>();
    if (is_data_uri(uri)) {
      std::string error;
      std::optional<DataUri> d = decode_data_uri(uri, error);
      if (!d) fail(path_, where + ": " + error);
      buf.origin = Buffer::Origin::DataUri;
      buf.data_prefix = std::move(d->prefix);
      buf.bytes = std::move(d->bytes);
    } else {
      std::string name;
      if (!uri_decode(uri, name)) fail(path_, fmt::format("{}: malformed uri {}", where, io_detail::quote(uri)));
      if (is_remote_or_absolute(name))
        fail(path_, fmt::format("{}: uri '{}' is not a file beside the glTF file", where, uri));
      buf.origin = Buffer::Origin::File;
      buf.file = (std::filesystem::path(f_.folder) / name).string();
      try {
        buf.bytes = read_file(buf.file);
      } catch (const IoError& e) {
        fail(path_, fmt::format("{}: cannot read '{}': {}", where, uri, e.message()));
      }
    }
    check_length(b);
    return buf.bytes;
  }

  void check_length(int b) {
    Buffer& buf = f_.buffers[static_cast<std::size_t>(b)];
    const std::uint64_t length = f_.json["buffers"][static_cast<std::size_t>(b)]["byteLength"].get<std::uint64_t>();
    if (buf.bytes.size() < length)
      fail(path_, fmt::format("buffer {} holds {} bytes, its byteLength is {}", b, buf.bytes.size(), length));
    buf.loaded = true;
  }

  GltfFile& f_;
  const std::string& path_;
};

struct Instance {
  int node = 0;
  int mesh = 0;
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

Eigen::Matrix4d local_matrix(const Json& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (const auto it = node.find("matrix"); it != node.end()) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m(r, c) = (*it)[static_cast<std::size_t>(c * 4 + r)].get<double>();  // column-major
    return m;
  }
  const auto vec = [&](const char* key, Eigen::Vector4d fallback) {
    if (const auto it = node.find(key); it != node.end())
      for (std::size_t i = 0; i < it->size(); ++i) fallback[static_cast<int>(i)] = (*it)[i].get<double>();
    return fallback;
  };
  const Eigen::Vector4d t = vec("translation", Eigen::Vector4d::Zero()), s = vec("scale", Eigen::Vector4d::Ones());
  const Eigen::Vector4d r = vec("rotation", Eigen::Vector4d(0, 0, 0, 1));  // x, y, z, w
  Eigen::Quaterniond q(r[3], r[0], r[1], r[2]);
  if (q.norm() > 0) q.normalize();
  m.topLeftCorner<3, 3>() = q.toRotationMatrix() * s.head<3>().asDiagonal();
  m.topRightCorner<3, 1>() = t.head<3>();
  return m;
}

// The nodes with a mesh, in depth-first order of the default scene (or of the root nodes when
// the file has no scene), with their world transforms.
std::vector<Instance> scene_instances(const Json& json, const std::string& path) {
  const std::size_t n = array_size(json, "nodes");
  std::vector<int> roots;
  if (array_size(json, "scenes") > 0) {
    const Json& scene = json["scenes"][json.contains("scene") ? json["scene"].get<std::size_t>() : 0];
    if (scene.contains("nodes"))
      for (const Json& r : scene["nodes"]) roots.push_back(r.get<int>());
  } else {
    std::vector<char> child(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (json["nodes"][i].contains("children"))
        for (const Json& c : json["nodes"][i]["children"]) child[c.get<std::size_t>()] = 1;
    for (std::size_t i = 0; i < n; ++i)
      if (!child[i]) roots.push_back(static_cast<int>(i));
  }
  std::vector<Instance> out;
  std::vector<char> seen(n, 0);
  std::vector<std::pair<int, Eigen::Matrix4d>> stack;
  for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, Eigen::Matrix4d::Identity());
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    if (seen[static_cast<std::size_t>(node)])
      fail(path, fmt::format("node {} is reached twice in the node hierarchy (a node has one parent at most, and "
                             "the hierarchy no cycle)", node));
    seen[static_cast<std::size_t>(node)] = 1;
    const Json& j = json["nodes"][static_cast<std::size_t>(node)];
    const Eigen::Matrix4d world = parent * local_matrix(j);
    if (j.contains("mesh")) {
      Instance in{node, j["mesh"].get<int>()};
      if (!j.contains("skin")) {  // a skinned mesh ignores its node's transform (glTF 2.0, 3.7.3)
        in.linear = world.topLeftCorner<3, 3>();
        in.translation = world.topRightCorner<3, 1>();
      }
      out.push_back(in);
    }
    if (j.contains("children"))
      for (auto c = j["children"].rbegin(); c != j["children"].rend(); ++c) stack.emplace_back(c->get<int>(), world);
  }
  return out;
}


std::vector<std::array<int, 3>> triangles(std::uint64_t mode, const std::vector<int>& v, const std::string& path,
                                          const std::string& where) {
  std::vector<std::array<int, 3>> out;
  if (mode == 4 && v.size() % 3 != 0)
    fail(path, fmt::format("{}: {} vertex indices do not make whole triangles", where, v.size()));
  const std::size_t n = mode == 4 ? v.size() / 3 : (v.size() >= 3 ? v.size() - 2 : 0);
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (mode == 4) out.push_back({v[3 * i], v[3 * i + 1], v[3 * i + 2]});
    if (mode == 5) out.push_back({v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});  // strip (glTF 2.0, 3.7.2.1)
    if (mode == 6) out.push_back({v[i + 1], v[i + 2], v[0]});                   // fan
  }
  return out;
}

// Builds the soup and the attributes from the instances, primitive by primitive.
class Builder {
 public:
  Builder(GltfFile& f, Accessors& accessors, const std::string& path, ReadResult& out)
      : f_(f), acc_(accessors), path_(path), out_(out) {
    const std::size_t accessor_count = array_size(f.json, "accessors");
    position_block_.assign(accessor_count, -1);
    normal_block_.assign(accessor_count, -1);
    uv_base_.assign(accessor_count, -1);
    tangent_seen_.assign(accessor_count, 0);
    mesh_node_.assign(array_size(f.json, "meshes"), -1);
  }

  void add(const Instance& in) {
    const double det = in.linear.determinant();
    if (!(std::abs(det) > 0) || !std::isfinite(det) || !in.translation.allFinite()) {
      out_.warnings.push_back(fmt::format("node {} has a singular transform: its mesh {} is not deformed", in.node, in.mesh));
      return;
    }
    int& first = mesh_node_[static_cast<std::size_t>(in.mesh)];
    if (first >= 0) {  // instancing: the data is shared, so only one instance can be deformed
      instances_[in.mesh].push_back(in.node);
      return;
    }
    first = in.node;
    const Json& primitives = f_.json["meshes"][static_cast<std::size_t>(in.mesh)]["primitives"];
    for (std::size_t p = 0; p < primitives.size(); ++p) primitive(in, static_cast<int>(p));
  }

  int skipped_lines() const { return skipped_lines_; }

  void finish() {
    if (skipped_lines_ > 0)
      out_.warnings.push_back(fmt::format("{} primitives of points or lines skipped (only triangles are deformed)", skipped_lines_));
    if (no_position_ > 0) out_.warnings.push_back(fmt::format("{} primitives without POSITION skipped", no_position_));
    for (const auto& [mesh, nodes] : instances_) {
      const int first = mesh_node_[static_cast<std::size_t>(mesh)];
      std::string list = std::to_string(first);
      for (const int n : nodes) list += ", " + std::to_string(n);
      out_.warnings.push_back(fmt::format("mesh {} is instanced by nodes {}: only node {}'s instance is deformed (the "
                                          "others share its data and follow it)", mesh, list, first));
    }
    if (!shared_.empty()) {
      std::string list;
      for (const int m : shared_) list += (list.empty() ? "" : ", ") + std::to_string(m);
      out_.warnings.push_back(fmt::format("meshes {} use POSITION data of a node under another transform: they follow "
                                          "its deformation", list));
    }
    MeshAttributes& a = out_.attributes;
    if (a.normal.values.empty()) a.normal = {};
    if (a.uv.values.empty()) a.uv = {};
    if (color_width_ > 0) {
      NamedAttribute color{"color", color_width_, {}};
      for (const Eigen::Vector4d& c : color_)
        for (int k = 0; k < color_width_; ++k) color.values.push_back(c[k]);
      a.vertex.push_back(std::move(color));
    }
    std::string why;
    if (skipped_lines_ > 0) why = fmt::format(" ({} primitives of points or lines skipped)", skipped_lines_);
    if (out_.soup.positions.empty() && why.empty()) fail(path_, "no vertices");
    if (out_.soup.faces.empty()) fail(path_, "no faces" + why);
  }

 private:
  void primitive(const Instance& in, int p) {
    const Json& prim = f_.json["meshes"][static_cast<std::size_t>(in.mesh)]["primitives"][static_cast<std::size_t>(p)];
    const std::string where = fmt::format("mesh {} primitive {}", in.mesh, p);
    const std::uint64_t mode = uint_or(prim, "mode", 4);
    if (mode > 6) fail(path_, fmt::format("{}: unknown mode {}", where, mode));
    if (mode < 4) {
      ++skipped_lines_;
      return;
    }
    if (prim.contains("extensions") && prim["extensions"].contains("KHR_draco_mesh_compression"))
      fail(path_, where + ": KHR_draco_mesh_compression is not supported (its compressed copy would keep the old shape)");
    const Json& attributes = prim["attributes"];
    if (!attributes.contains("POSITION")) {
      ++no_position_;
      return;
    }
    const int block = position_block(attributes["POSITION"].get<int>(), in);
    if (block < 0) return;
    const int n = f_.positions[static_cast<std::size_t>(block)].layout.count;
    const auto tris = triangles(mode, indices(prim, n, where), path_, where);
    if (tris.size() > io_detail::kMaxElements - out_.soup.faces.size()) fail(path_, "more than 2^31-1 triangles");
    const int normal_base = attributes.contains("NORMAL") ? normal_rows(attributes["NORMAL"].get<int>(), in, n, where) : -1;
    const int uv_base = attributes.contains("TEXCOORD_0") ? uv_rows(attributes["TEXCOORD_0"].get<int>(), n, where) : -1;
    const std::vector<int>& vertex = f_.positions[static_cast<std::size_t>(block)].vertex;
    if (attributes.contains("COLOR_0")) colors(attributes["COLOR_0"].get<int>(), vertex, where);
    if (attributes.contains("TANGENT") && normal_base >= 0)
      tangents(attributes["TANGENT"].get<int>(), attributes["NORMAL"].get<int>(), n, where);
    MeshAttributes& a = out_.attributes;
    for (const auto& t : tris) {
      const Tri tri{vertex[static_cast<std::size_t>(t[0])], vertex[static_cast<std::size_t>(t[1])],
                    vertex[static_cast<std::size_t>(t[2])]};
      a.triangle_polygon.push_back(static_cast<int>(out_.soup.faces.size()));
      out_.soup.faces.push_back(tri);
      a.polygons.add(tri);
      for (const int k : t) {
        a.normal.index.push_back(normal_base < 0 ? -1 : normal_base + k);
        a.uv.index.push_back(uv_base < 0 ? -1 : uv_base + k);
      }
    }
  }

  // The block of POSITION accessor `a`, welding its elements in world space on first use;
  // -1 (with a warning) when another node with another transform already uses it.
  int position_block(int a, const Instance& in) {
    int& block = position_block_[static_cast<std::size_t>(a)];
    if (block >= 0) {
      const PositionBlock& b = f_.positions[static_cast<std::size_t>(block)];
      if (b.linear == in.linear && b.translation == in.translation) return block;
      shared_.push_back(in.mesh);
      return -1;
    }
    PositionBlock b{acc_.float_layout(a, 3, "POSITION"), in.linear, in.translation, {}};
    b.vertex.resize(static_cast<std::size_t>(b.layout.count));
    weld_.reserve(out_.soup.positions.size() + b.vertex.size());
    for (int i = 0; i < b.layout.count; ++i) {
      const Eigen::Vector3d p = acc_.vec3(b.layout, i);
      if (!p.allFinite()) fail(path_, fmt::format("accessor {} (POSITION): element {} is not finite", a, i));
      const Eigen::Vector3d w = in.linear * p + in.translation;
      if (!w.allFinite()) fail(path_, fmt::format("node {}: element {} of accessor {} is not finite in world space", in.node, i, a));
      b.vertex[static_cast<std::size_t>(i)] = weld(w);
    }
    block = static_cast<int>(f_.positions.size());
    f_.positions.push_back(std::move(b));
    return block;
  }

  int weld(const Eigen::Vector3d& w) {
    if (out_.soup.positions.size() >= io_detail::kMaxElements) fail(path_, "more than 2^31-1 vertices");
    const auto [vertex, inserted] = weld_.add(w);
    if (inserted) {
      color_.emplace_back(1, 1, 1, 1);
      has_color_.push_back(0);
    }
    return vertex;
  }

  std::vector<int> indices(const Json& prim, int n, const std::string& where) {
    std::vector<int> out;
    if (!prim.contains("indices")) {
      out.resize(static_cast<std::size_t>(n));
      std::iota(out.begin(), out.end(), 0);
      return out;
    }
    const int a = prim["indices"].get<int>();
    const Accessor acc = acc_.accessor(a);
    const std::string what = fmt::format("accessor {} (indices of {})", a, where);
    if (acc.components != 1 || acc.normalized ||
        (acc.component_type != kUByte && acc.component_type != kUShort && acc.component_type != kUInt))
      fail(path_, what + ": must be SCALAR unsigned byte, short or int");
    if (!acc.has_view) fail(path_, what + ": has no bufferView");
    const std::vector<double> values = acc_.values(acc, what);
    out.reserve(values.size());
    for (const double v : values) {
      if (v >= n) fail(path_, fmt::format("accessor {}: index {} out of range ({} vertices)", a, static_cast<std::uint64_t>(v), n));
      out.push_back(static_cast<int>(v));
    }
    return out;
  }

  void check_count(const Accessor& acc, int n, const char* semantic, const std::string& where) {
    if (acc.count != n)
      fail(path_, fmt::format("{}: {} (accessor {}) has {} elements, POSITION has {}", where, semantic, acc.index, acc.count, n));
  }

  // Rows of the world-space normals of NORMAL accessor `a` (added on first use).
  int normal_rows(int a, const Instance& in, int n, const std::string& where) {
    int& block = normal_block_[static_cast<std::size_t>(a)];
    if (block >= 0) return f_.normals[static_cast<std::size_t>(block)].row_base;
    check_count(acc_.accessor(a), n, "NORMAL", where);
    const Layout l = acc_.float_layout(a, 3, "NORMAL");
    CornerAttribute& normal = out_.attributes.normal;
    normal.width = 3;
    const int base = normal.rows();
    const Eigen::Matrix3d to_world = in.linear.inverse().transpose();
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d v = acc_.vec3(l, i);
      if (!v.allFinite()) fail(path_, fmt::format("accessor {} (NORMAL): element {} is not finite", a, i));
      Eigen::Vector3d w = to_world * v;
      if (w.norm() > 0) w.normalize();
      normal.values.insert(normal.values.end(), {w.x(), w.y(), w.z()});
    }
    block = static_cast<int>(f_.normals.size());
    f_.normals.push_back({l, base, in.linear.transpose()});
    return base;
  }

  void tangents(int a, int normal_accessor, int n, const std::string& where) {
    if (tangent_seen_[static_cast<std::size_t>(a)]) return;
    tangent_seen_[static_cast<std::size_t>(a)] = 1;
    check_count(acc_.accessor(a), n, "TANGENT", where);
    const NormalBlock& normal = f_.normals[static_cast<std::size_t>(normal_block_[static_cast<std::size_t>(normal_accessor)])];
    f_.tangents.push_back({acc_.float_layout(a, 4, "TANGENT"), normal.layout, normal.row_base});
  }

  // Texture coordinates with v up (OBJ, PLY): glTF's v runs down from the top of the image.
  int uv_rows(int a, int n, const std::string& where) {
    int& base = uv_base_[static_cast<std::size_t>(a)];
    if (base >= 0) return base;
    const Accessor acc = acc_.accessor(a);
    const std::string what = fmt::format("accessor {} (TEXCOORD_0)", a);
    if (acc.components != 2 || !(acc.component_type == kFloat || ((acc.component_type == kUByte || acc.component_type == kUShort) && acc.normalized)))
      fail(path_, what + ": must be VEC2 of float or normalized unsigned byte or short");
    check_count(acc, n, "TEXCOORD_0", where);
    const std::vector<double> v = acc_.values(acc, what);
    CornerAttribute& uv = out_.attributes.uv;
    uv.width = 2;
    base = uv.rows();
    for (std::size_t i = 0; i < v.size(); i += 2) uv.values.insert(uv.values.end(), {v[i], 1.0 - v[i + 1]});
    return base;
  }

  // COLOR_0 of each welded vertex: the first value seen.
  void colors(int a, const std::vector<int>& vertex, const std::string& where) {
    const Accessor acc = acc_.accessor(a);
    const std::string what = fmt::format("accessor {} (COLOR_0)", a);
    if ((acc.components != 3 && acc.components != 4) ||
        !(acc.component_type == kFloat || ((acc.component_type == kUByte || acc.component_type == kUShort) && acc.normalized)))
      fail(path_, what + ": must be VEC3 or VEC4 of float or normalized unsigned byte or short");
    check_count(acc, static_cast<int>(vertex.size()), "COLOR_0", where);
    const std::vector<double> v = acc_.values(acc, what);
    color_width_ = std::max(color_width_, acc.components);
    const auto k = static_cast<std::size_t>(acc.components);
    for (std::size_t i = 0; i < vertex.size(); ++i) {
      const auto s = static_cast<std::size_t>(vertex[i]);
      if (has_color_[s]) continue;
      has_color_[s] = 1;
      for (std::size_t c = 0; c < k; ++c) color_[s][static_cast<int>(c)] = v[i * k + c];
    }
  }

  GltfFile& f_;
  Accessors& acc_;
  const std::string& path_;
  ReadResult& out_;
  io_detail::PositionWelder weld_{out_.soup.positions};
  std::vector<int> position_block_, normal_block_, uv_base_;  // per accessor; -1: not read
  std::vector<char> tangent_seen_;
  std::vector<int> mesh_node_;  // per mesh: the node whose instance is deformed
  std::map<int, std::vector<int>> instances_;
  std::vector<int> shared_;  // meshes whose POSITION accessor another transform deforms
  int skipped_lines_ = 0, no_position_ = 0;
  std::vector<Eigen::Vector4d> color_;
  std::vector<char> has_color_;
  int color_width_ = 0;
};

// What a new file (another format, or write_gltf) would lose, for MeshBytes::dropped.
std::string kept_only_by_rewrite(const Json& json, int skipped_lines) {
  std::vector<std::string> kept;
  const auto has = [&](const char* key) { return array_size(json, key) > 0; };
  if (has("materials")) kept.emplace_back("materials");
  if (has("textures") || has("images")) kept.emplace_back("textures");
  bool targets = false;
  for (std::size_t m = 0; m < array_size(json, "meshes"); ++m)
    for (const Json& p : json["meshes"][m]["primitives"]) targets = targets || p.contains("targets");
  if (targets) kept.emplace_back("morph targets");
  if (has("skins")) kept.emplace_back("skins");
  if (has("animations")) kept.emplace_back("animations");
  if (has("cameras")) kept.emplace_back("cameras");
  if (array_size(json, "nodes") > 1) kept.emplace_back("the node hierarchy");
  if (skipped_lines > 0) kept.emplace_back("points and lines");
  if (json.contains("extensionsUsed")) kept.emplace_back("extensions");
  std::string out;
  for (std::size_t i = 0; i < kept.size(); ++i)
    out += (i == 0 ? "" : i + 1 == kept.size() ? " and " : ", ") + kept[i];
  return out;
}

void check_version(const Json& json, const std::string& path) {
  const std::string version = json["asset"]["version"].get<std::string>();
  if (version.rfind("2.", 0) != 0)
    fail(path, fmt::format("asset.version is {}: only glTF 2.x is supported", io_detail::quote(version)));
  if (json["asset"].contains("minVersion") && json["asset"]["minVersion"].get<std::string>() != "2.0")
    fail(path, fmt::format("asset.minVersion is {}: only glTF 2.0 is supported",
                           io_detail::quote(json["asset"]["minVersion"].get<std::string>())));
  if (!json.contains("extensionsRequired")) return;
  for (const Json& e : json["extensionsRequired"]) {
    const std::string name = e.get<std::string>();
    if (name == "KHR_draco_mesh_compression" || name == "KHR_mesh_quantization" || name == "EXT_meshopt_compression")
      fail(path, fmt::format("the file requires the extension {} (compressed or quantized geometry is not supported)", name));
  }
}

Json parse(std::string_view text, const std::string& path) {
  constexpr std::size_t kMaxDepth = 512;
  if (const std::size_t depth = json_depth(text); depth > kMaxDepth)
    fail(path, fmt::format("JSON nested {} levels deep (at most {} supported)", depth, kMaxDepth));
  try {
    return parse_json_text(text, path);
  } catch (const InvalidInput& e) {  // a repeated key: parse_json_text says "path: ..."
    std::string message = e.what();
    if (message.rfind(path + ": ", 0) == 0) message = message.substr(path.size() + 2);
    fail(path, message);
  }
}

}  // namespace
}  // namespace gltf_detail

void read_gltf(std::string_view data, const std::string& path, ReadResult& out) {
  using namespace gltf_detail;
  if (data.empty()) fail(path, "empty file");
  GltfFile f;
  std::optional<std::string_view> bin;
  std::string_view text = data;
  if (is_glb(data)) {
    const Glb glb = parse_glb(data, path);
    text = glb.json;
    while (!text.empty() && text.back() == '\0') text.remove_suffix(1);  // some exporters pad with NULs
    bin = glb.bin;
    f.glb = true;
    f.glb_rest = std::string(glb.rest);
  }
  f.json = parse(text, path);
  check_schema(f.json, path);
  check_version(f.json, path);
  f.json_text = std::string(text);
  f.folder = std::filesystem::path(path).parent_path().string();
  f.buffers.resize(array_size(f.json, "buffers"));
  Accessors accessors(f, path);
  if (bin) accessors.set_glb_bin(*bin);
  out.soup = {};
  out.attributes = {};
  Builder builder(f, accessors, path, out);
  for (const Instance& in : scene_instances(f.json, path)) builder.add(in);
  builder.finish();
  f.kept = kept_only_by_rewrite(f.json, builder.skipped_lines());
  // Keep only the buffers the rewrite patches and buffer 0 (a BIN chunk, written back whole, or
  // what becomes the BIN chunk when a .gltf is written as a .glb).
  std::vector<char> keep(f.buffers.size(), 0);
  if (!keep.empty()) keep[0] = 1;
  for (const PositionBlock& b : f.positions) keep[static_cast<std::size_t>(b.layout.buffer)] = 1;
  for (const NormalBlock& b : f.normals) keep[static_cast<std::size_t>(b.layout.buffer)] = 1;
  for (const TangentBlock& b : f.tangents) keep[static_cast<std::size_t>(b.layout.buffer)] = 1;
  for (std::size_t b = 0; b < f.buffers.size(); ++b)
    if (!keep[b] && f.buffers[b].origin != Buffer::Origin::Glb) f.buffers[b] = {};
  out.format = MeshFormat::Gltf;
  out.source = std::make_shared<const GltfSource>(std::move(f));
}

}  // namespace freeform
