// Writing a read glTF back with new positions: the POSITION, NORMAL and TANGENT bytes of the
// moved vertices are patched in a copy of their buffers, the accessors' min/max updated, and
// nothing else in the JSON or the buffers changes. Vertices that did not move keep their bytes.
#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/gltf_source.h"
#include "freeform/io/gltf_util.h"
#include "freeform/io/mesh_io.h"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <system_error>

namespace freeform::gltf_detail {
namespace {

namespace fs = std::filesystem;

unsigned char* element(std::string& bytes, const Layout& l, int i) {
  return reinterpret_cast<unsigned char*>(bytes.data()) + l.start + static_cast<std::size_t>(i) * l.stride;
}

Eigen::Vector4d read(std::string& bytes, const Layout& l, int i, int n) {
  const unsigned char* p = element(bytes, l, i);
  Eigen::Vector4d v = Eigen::Vector4d::Zero();
  for (int c = 0; c < n; ++c) v[c] = load_le<float>(p + 4 * c);
  return v;
}

void write(std::string& bytes, const Layout& l, int i, const Eigen::Vector4d& v, int n) {
  unsigned char* p = element(bytes, l, i);
  for (int c = 0; c < n; ++c) store_le(p + 4 * c, static_cast<float>(v[c]));
}

class Rewriter {
 public:
  Rewriter(const GltfFile& f, const ReadResult& file, std::span<const Vec3> positions, const std::string& out_path)
      : f_(f), file_(file), positions_(positions), out_path_(out_path), json_(f.json), patched_(f.buffers.size()) {
    const std::vector<Vec3>& old = file.soup.positions;
    if (positions.size() != old.size())
      throw InvalidInput(fmt::format("{}: {} positions given for a mesh of {} vertices", out_path, positions.size(), old.size()));
    moved_.resize(old.size());
    for (std::size_t v = 0; v < old.size(); ++v) moved_[v] = positions[v] != old[v];
  }

  void write_positions() {
    for (const PositionBlock& b : f_.positions) {
      const Eigen::Matrix3d inverse = b.linear.inverse();
      bool touched = false;
      for (int i = 0; i < b.layout.count; ++i) {
        const auto v = static_cast<std::size_t>(b.vertex[static_cast<std::size_t>(i)]);
        if (!moved_[v]) continue;
        touched = true;
        const Eigen::Vector3d local = inverse * (positions_[v] - b.translation);
        if (!local.cast<float>().allFinite())
          throw InvalidInput(fmt::format("{}: cannot write vertex {}: a coordinate is beyond the single precision of glTF",
                                         out_path_, v));
        write(bytes(b.layout.buffer), b.layout, i, Eigen::Vector4d(local.x(), local.y(), local.z(), 0), 3);
      }
      if (touched) update_bounds(b.layout, 3);
    }
  }

  // The normals of the polygons around moved vertices, recomputed in world space and turned
  // back into each node's frame; the tangents beside them made orthogonal to them again.
  void write_normals() {
    const CornerAttribute& normal = file_.attributes.normal;
    const Polygons& polygons = file_.attributes.polygons;
    if (f_.normals.empty() || normal.width != 3 || normal.index.size() != polygons.corners.size()) return;
    std::vector<char> touched(static_cast<std::size_t>(normal.rows()), 0);
    for (int p = 0; p < polygons.size(); ++p) {
      const auto begin = static_cast<std::size_t>(polygons.offsets[static_cast<std::size_t>(p)]);
      const auto end = static_cast<std::size_t>(polygons.offsets[static_cast<std::size_t>(p) + 1]);
      bool moved = false;
      for (std::size_t c = begin; c < end; ++c) {
        const auto v = static_cast<std::size_t>(polygons.corners[c]);
        moved = moved || (v < moved_.size() && moved_[v]);
      }
      for (std::size_t c = begin; moved && c < end; ++c)
        if (normal.index[c] >= 0 && normal.index[c] < normal.rows()) touched[static_cast<std::size_t>(normal.index[c])] = 1;
    }
    const std::vector<double> values = recomputed_normals(polygons, normal, positions_);
    for (const NormalBlock& b : f_.normals) {
      bool any = false;
      for (int i = 0; i < b.layout.count; ++i) {
        const auto row = static_cast<std::size_t>(b.row_base + i);
        if (row >= touched.size() || !touched[row]) continue;
        Eigen::Vector3d n = b.to_local * Eigen::Vector3d(values[3 * row], values[3 * row + 1], values[3 * row + 2]);
        if (!(n.norm() > 0)) continue;
        n.normalize();
        write(bytes(b.layout.buffer), b.layout, i, Eigen::Vector4d(n.x(), n.y(), n.z(), 0), 3);
        any = true;
      }
      if (any) update_bounds(b.layout, 3);
    }
    for (const TangentBlock& b : f_.tangents) write_tangents(b, touched);
  }

  // The file in the container of the output path (.glb: binary, anything else: JSON text).
  // .gltf to .glb: buffer 0 (an external file or a data: URI) becomes the BIN chunk, the only
  // buffer the spec lets a .glb embed; the others keep their uri. .glb to .gltf: the BIN chunk
  // becomes a companion .bin file (the chunks after it, unknown to glTF 2.0, have no place in a
  // .gltf and are left out). Patched buffers of other files become new companion files, patched
  // data: URIs are encoded again.
  std::string assemble(std::vector<std::pair<std::string, std::string>>& companions) {
    const bool glb_out = lower_extension(out_path_) == ".glb";
    const bool bin_in = !f_.buffers.empty() && f_.buffers[0].origin == Buffer::Origin::Glb;
    const bool embed = glb_out && !bin_in && embeddable();  // buffer 0 of a .gltf into the BIN chunk
    std::vector<char> to_file(f_.buffers.size(), 0);
    int files = 0;
    for (std::size_t b = 0; b < f_.buffers.size(); ++b) {
      const Buffer::Origin origin = f_.buffers[b].origin;
      to_file[b] = b == 0 && (embed || bin_in) ? (bin_in && !glb_out)
                                               : patched_[b] && origin == Buffer::Origin::File;
      files += to_file[b];
    }
    std::string_view bin;  // the BIN chunk of a .glb output
    const bool has_bin = glb_out && (bin_in || embed);
    if (has_bin) bin = embed ? whole(0).substr(0, byte_length(0)) : whole(0);
    if (embed) json_["buffers"][0].erase("uri");
    for (std::size_t b = 0; b < f_.buffers.size(); ++b) {
      if (to_file[b]) {
        const std::string name = companion_name(files > 1 ? fmt::format("_{}", b) : std::string());
        json_["buffers"][b]["uri"] = uri_encode(name);
        std::string data = patched_[b] ? std::move(*patched_[b]) : std::string(whole(static_cast<int>(b)));
        data.resize(std::min(data.size(), byte_length(b)));  // no BIN chunk padding
        companions.emplace_back(name, std::move(data));
        patched_[b].reset();
      } else if (patched_[b] && f_.buffers[b].origin == Buffer::Origin::DataUri && !(b == 0 && embed)) {
        json_["buffers"][b]["uri"] = f_.buffers[b].data_prefix + base64_encode(*patched_[b]);
      }
    }
    if (!same_folder()) carry_external_files(to_file, embed, companions);
    const std::string text = dump_like(json_, f_.json_text);
    if (!glb_out) return text;
    // 12 bytes of header, 8 per chunk, and up to 3 of padding per chunk.
    if (text.size() + bin.size() + f_.glb_rest.size() + 12 + 16 + 6 > std::numeric_limits<std::uint32_t>::max())
      throw InvalidInput(fmt::format("{}: a .glb holds at most 4 GiB; this file would be larger (write a .gltf instead)", out_path_));
    return build_glb(text, bin, has_bin, f_.glb_rest);
  }

 private:
  void write_tangents(const TangentBlock& b, const std::vector<char>& touched) {
    bool any = false;
    for (int i = 0; i < b.layout.count; ++i) {
      const auto row = static_cast<std::size_t>(b.row_base + i);
      if (row >= touched.size() || !touched[row]) continue;
      const Eigen::Vector3d n = read(bytes(b.normal.buffer), b.normal, i, 3).head<3>().normalized();
      Eigen::Vector4d t = read(bytes(b.layout.buffer), b.layout, i, 4);
      Eigen::Vector3d d = t.head<3>() - n * n.dot(t.head<3>());
      d = d.norm() > 1e-12 ? d.normalized() : n.unitOrthogonal();
      t.head<3>() = d;
      write(bytes(b.layout.buffer), b.layout, i, t, 3);  // w (handedness) kept
      any = true;
    }
    if (any) update_bounds(b.layout, 4);
  }

  // Whether buffer 0 of a .gltf can become the BIN chunk: it was read, or it is a data: URI or
  // a file beside the glTF (not a remote or absolute uri, which stays a uri).
  bool embeddable() const {
    if (f_.buffers.empty()) return false;
    if (f_.buffers[0].loaded) return true;
    const Json& buffer = f_.json["buffers"][0];
    if (!buffer.contains("uri")) return false;
    const std::string uri = buffer["uri"].get<std::string>();
    std::string name;
    return is_data_uri(uri) || (uri_decode(uri, name) && !is_remote_or_absolute(name));
  }

  std::size_t byte_length(std::size_t b) const { return f_.json["buffers"][b]["byteLength"].get<std::size_t>(); }

  // All bytes of buffer b: patched, as read, or (buffer 0, which no mesh the reader used
  // refers to) read now from its data: URI or file.
  std::string_view whole(int b) {
    const auto i = static_cast<std::size_t>(b);
    if (patched_[i]) return *patched_[i];
    if (f_.buffers[i].loaded) return f_.buffers[i].bytes;
    FF_CHECK(b == 0, "only buffer 0 is read when writing");
    if (!unread_) unread_ = read_unread_buffer0();
    return *unread_;
  }

  std::string read_unread_buffer0() const {
    const std::string uri = f_.json["buffers"][0]["uri"].get<std::string>();
    std::string bytes;
    if (is_data_uri(uri)) {
      std::string error;
      std::optional<DataUri> d = decode_data_uri(uri, error);
      if (!d) throw InvalidInput(fmt::format("{}: cannot embed buffer 0: {}", out_path_, error));
      bytes = std::move(d->bytes);
    } else {
      std::string name;
      uri_decode(uri, name);  // checked by embeddable()
      const std::string file = (fs::path(f_.folder) / name).string();
      try {
        bytes = read_file(file);
      } catch (const IoError& e) {
        throw IoError(file, 0, fmt::format("cannot embed buffer 0 in {}: {}", out_path_, e.message()));
      }
    }
    if (bytes.size() < byte_length(0))
      throw InvalidInput(fmt::format("{}: cannot embed buffer 0: it holds {} bytes, its byteLength is {}", out_path_,
                                     bytes.size(), byte_length(0)));
    return bytes;
  }

  static std::string lower_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
  }

  std::string& bytes(int b) {
    std::optional<std::string>& p = patched_[static_cast<std::size_t>(b)];
    if (!p) p = f_.buffers[static_cast<std::size_t>(b)].bytes;
    return *p;
  }

  // min/max of an accessor that has them, from the bytes as written.
  void update_bounds(const Layout& l, int n) {
    Json& a = json_["accessors"][static_cast<std::size_t>(l.accessor)];
    if (!a.contains("min") && !a.contains("max")) return;
    Eigen::Vector4d lo = Eigen::Vector4d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int i = 0; i < l.count; ++i) {
      const Eigen::Vector4d v = read(bytes(l.buffer), l, i, n);
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    Json jl = Json::array(), jh = Json::array();
    for (int c = 0; c < n; ++c) {
      jl.push_back(lo[c]);
      jh.push_back(hi[c]);
    }
    if (a.contains("min")) a["min"] = std::move(jl);
    if (a.contains("max")) a["max"] = std::move(jh);
  }

  // "<output stem><suffix>.bin", numbered further if that names a file the input or the output
  // refers to (never overwrite a buffer or image still in use).
  std::string companion_name(const std::string& suffix) {
    const fs::path out(out_path_);
    return free_name((out.stem().empty() ? std::string("mesh") : out.stem().string()) + suffix, ".bin");
  }

  // stem + ext beside the output, "stem-1" + ext and so on if that is taken: by the output, a
  // file the input refers to, another companion, or a different file already there.
  std::string free_name(const std::string& stem, const std::string& ext, const std::string* content = nullptr) {
    const fs::path folder = fs::path(out_path_).parent_path();
    for (int k = 0;; ++k) {
      const std::string name = stem + (k == 0 ? std::string() : fmt::format("-{}", k)) + ext;
      const std::string path = (folder / name).string();
      if (taken_.count(name) || clashes(path, content != nullptr)) continue;
      std::error_code ec;
      if (content && fs::exists(path, ec) && !same_bytes(path, *content)) continue;
      taken_.insert(name);
      return name;
    }
  }

  static bool same_bytes(const std::string& path, const std::string& content) {
    try {
      return read_file(path) == content;
    } catch (const IoError&) {
      return false;
    }
  }

  // Whether the output lies in the input's folder, where the input's relative uris still resolve.
  bool same_folder() const { return same_file(f_.folder.empty() ? "." : f_.folder, folder_of(out_path_)); }

  // The input's files that a relative uri names (buffers the output does not write anew, and
  // images) are not beside an output in another folder: they become companions there, under
  // their own names where free, and the uris name those. A file that cannot be read (one no
  // mesh needed) keeps its uri: the input's was dangling too.
  void carry_external_files(const std::vector<char>& to_file, bool embed,
                            std::vector<std::pair<std::string, std::string>>& companions) {
    for (std::size_t b = 0; b < f_.buffers.size(); ++b) {
      if (to_file[b] || (b == 0 && embed) || f_.buffers[b].origin != Buffer::Origin::File) continue;
      carry(json_["buffers"][b], f_.buffers[b].loaded ? &f_.buffers[b].bytes : nullptr, companions);
    }
    if (json_.contains("images"))
      for (Json& image : json_["images"]) carry(image, nullptr, companions);
  }

  // One buffer or image: its bytes (`read`, or its file's) under a free name beside the output.
  void carry(Json& item, const std::string* read, std::vector<std::pair<std::string, std::string>>& companions) {
    std::string name, data;
    if (!relative_file(item, name)) return;
    if (read) {
      data = *read;
    } else {
      try {
        data = read_file((fs::path(f_.folder) / name).string());
      } catch (const IoError&) {
        return;
      }
    }
    const fs::path original(name);
    const std::string copy = free_name(original.stem().string(), original.extension().string(), &data);
    item["uri"] = uri_encode(copy);
    companions.emplace_back(copy, std::move(data));
  }

  // The file name a uri refers to, when it is a relative path (not a data: URI, remote or absolute).
  static bool relative_file(const Json& item, std::string& name) {
    if (!item.contains("uri") || !item["uri"].is_string()) return false;
    const std::string uri = item["uri"].get<std::string>();
    return !is_data_uri(uri) && uri_decode(uri, name) && !is_remote_or_absolute(name);
  }

  // A carried file may take the name its original has beside the input (never the original
  // itself): the output's folder is another one.
  bool clashes(const std::string& candidate, bool carried) const {
    if (same_file(candidate, out_path_)) return true;
    for (const char* list : {"buffers", "images"}) {
      if (!f_.json.contains(list)) continue;
      for (const Json& item : f_.json[list]) {
        std::string name;
        if (!item.contains("uri") || is_data_uri(item["uri"].get<std::string>()) ||
            !uri_decode(item["uri"].get<std::string>(), name) || is_remote_or_absolute(name))
          continue;
        if (same_file(candidate, (fs::path(f_.folder) / name).string()) ||
            (!carried && same_file(candidate, (fs::path(out_path_).parent_path() / name).string())))
          return true;
      }
    }
    return false;
  }

  const GltfFile& f_;
  const ReadResult& file_;
  std::span<const Vec3> positions_;
  const std::string& out_path_;
  Json json_;
  std::vector<std::optional<std::string>> patched_;  // copies of the buffers written to
  std::optional<std::string> unread_;                 // buffer 0, when the reader had not read it
  std::vector<char> moved_;
  std::set<std::string> taken_;  // companion names chosen
};

}  // namespace

std::string GltfSource::rewrite(const ReadResult& file, std::span<const Vec3> positions,
                                std::vector<std::pair<std::string, std::string>>& companions,
                                const std::string& out_path) const {
  Rewriter r(file_, file, positions, out_path);
  r.write_positions();
  r.write_normals();
  return r.assemble(companions);
}

}  // namespace freeform::gltf_detail
