// A PLY file as read, rewritten with new positions: only the vertex element's x, y, z and
// nx, ny, nz values change, in the file's own encoding; everything else stays byte for byte.
#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/ply_header.h"
#include "freeform/io/ply_layout.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <string_view>
#include <utility>

namespace freeform::ply_detail {
namespace {

// What the attributes do not hold: other elements, list properties, comments.
std::string not_exposed(const Header& header, const Layout& layout) {
  std::vector<std::string> parts;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& el = header.elements[e];
    if (e != layout.vertex_element && e != layout.face_element) {
      if (el.count > 0) parts.push_back(fmt::format("the element '{}'", el.name));
      continue;
    }
    for (std::size_t p = 0; p < el.props.size(); ++p)
      if (el.props[p].is_list && layout.fields[e][p].role != Role::Indices)
        parts.push_back(fmt::format("the list property '{}' of '{}'", el.props[p].name, el.name));
  }
  if (header.has_comments) parts.push_back("comments");
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i)
    out += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return out;
}

void copy_on_huge_pages(std::string_view from, std::string& to) {
  reserve_huge(to, from.size());
  to.assign(from);
}

// Keeps the file's bytes and its vertex element's layout; a rewrite walks the vertex element
// again (cheap next to reading it) instead of keeping per-vertex offsets.
class PlySource final : public FileSource {
 public:
  PlySource(std::shared_ptr<const std::string> data, const std::string& name, const Header& header, const Layout& layout,
            std::size_t vertex_offset)
      : name_(name),
        encoding_(header.encoding),
        vertex_offset_(vertex_offset),
        vertex_count_(layout.vertex_count),
        props_(header.elements[layout.vertex_element].props) {
    for (const Field& f : layout.fields[layout.vertex_element]) {
      const bool kept = is_position(f.role) || is_normal(f.role);
      roles_.push_back(kept ? f.role : Role::Skip);
      has_normals_ = has_normals_ || f.role == Role::NX;
    }
    kept_only_ = not_exposed(header, layout);
    header_end_ = header.body_offset;
    data_ = std::move(data);
  }

  std::string rewrite(const ReadResult& file, std::span<const Vec3> positions,
                      std::vector<std::pair<std::string, std::string>>& /*companions*/,
                      const std::string& out_path) const override {
    if (positions.size() != vertex_count_)
      throw InvalidInput(fmt::format("cannot write {}: {} positions given for the {} vertices of the PLY file",
                                     out_path, positions.size(), vertex_count_));
    std::vector<double> normals;
    if (has_normals_) {
      // Normals of polygons that kept their positions stay as the file has them.
      std::span<const Vec3> old = file.soup.positions;
      if (old.size() != vertex_count_) old = {};
      normals = recomputed_normals(file.attributes.polygons, file.attributes.normal, positions, old);
    }
    if (normals.size() != 3 * vertex_count_) normals.clear();  // not this file's attributes: keep its normals
    return relink_texture_files(
        encoding_ == Encoding::Ascii ? rewrite_ascii(positions, normals) : rewrite_binary(positions, normals),
        out_path);
  }

  bool binary() const override { return encoding_ != Encoding::Ascii; }
  std::string kept_only_by_rewrite() const override { return kept_only_; }

 private:
  // MeshLab names a texture in the header ("comment TextureFile name"), relative to the file's
  // folder: written into another folder, the name becomes the path from there (file_util.h).
  std::string relink_texture_files(std::string out, const std::string& out_path) const {
    constexpr std::string_view kTexture = "comment TextureFile ";
    const std::string from = folder_of(name_), to = folder_of(out_path);
    if (std::string_view(out).substr(0, header_end_).find(kTexture) == std::string_view::npos || same_file(from, to))
      return out;
    std::string header;
    for (std::size_t begin = 0; begin < header_end_;) {
      const std::size_t newline = out.find('\n', begin);
      const std::size_t end = newline == std::string::npos ? header_end_ : std::min(newline + 1, header_end_);
      const std::string_view line = std::string_view(out).substr(begin, end - begin);
      std::size_t n = line.size();
      while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r')) --n;
      if (line.starts_with(kTexture) && n > kTexture.size()) {
        header.append(kTexture).append(reference_from(line.substr(kTexture.size(), n - kTexture.size()), from, to));
        header.append(line.substr(n));
      } else {
        header.append(line);
      }
      begin = end;
    }
    return header + out.substr(header_end_);
  }

  // The value property `role` of vertex v gets, or nullopt to keep the file's.
  static std::optional<double> new_value(Role role, std::size_t v, std::span<const Vec3> positions,
                                         const std::vector<double>& normals) {
    if (is_position(role)) return positions[v][component_of(role)];
    if (role == Role::Skip || normals.empty()) return std::nullopt;
    return normals[v * 3 + static_cast<std::size_t>(component_of(role))];
  }

  std::string rewrite_binary(std::span<const Vec3> positions, const std::vector<double>& normals) const {
    std::string out;
    copy_on_huge_pages(*data_, out);
    auto* p = reinterpret_cast<unsigned char*>(out.data());
    const bool swap = needs_swap(encoding_);
    std::size_t pos = vertex_offset_;
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      for (std::size_t k = 0; k < props_.size(); ++k) {
        const Property& prop = props_[k];
        if (prop.is_list) {
          FF_CHECK(pos + scalar_size(prop.count_type) <= out.size(), "PLY vertex list past the end of the file");
          const auto count = static_cast<std::size_t>(load_int(prop.count_type, p + pos, swap));
          pos += scalar_size(prop.count_type) + count * scalar_size(prop.type);
          continue;
        }
        FF_CHECK(pos + scalar_size(prop.type) <= out.size(), "PLY vertex past the end of the file");
        const std::optional<double> value = new_value(roles_[k], v, positions, normals);
        // An unchanged value keeps its bytes (a -0 stays -0).
        if (value && !same_value(to_type(prop.type, *value), load_double(prop.type, p + pos, swap)))
          store_value(prop.type, *value, p + pos, swap);
        pos += scalar_size(prop.type);
      }
    }
    return out;
  }

  // Copies the text and replaces only the tokens whose value changes in the property's type, so
  // unchanged values keep their spelling ("1.000000") and every line keeps its spacing.
  std::string rewrite_ascii(std::span<const Vec3> positions, const std::vector<double>& normals) const {
    std::string out;
    reserve_huge(out, data_->size() + data_->size() / 4);
    const std::string_view rest = std::string_view(*data_).substr(vertex_offset_);
    io_detail::TokenReader tokens(rest, 1, name_);
    std::size_t copied = 0;  // in `rest`
    out.append(*data_, 0, vertex_offset_);
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      for (std::size_t k = 0; k < props_.size(); ++k) {
        const std::string_view tok = tokens.require("a vertex value");
        if (props_[k].is_list) {
          std::int64_t count = 0;
          io_detail::parse_int(tok, count);
          for (std::int64_t j = 0; j < count; ++j) tokens.require("a vertex value");
          continue;
        }
        const std::optional<double> value = new_value(roles_[k], v, positions, normals);
        if (!value) continue;
        double old = 0;
        io_detail::parse_double(tok, old);  // checked when the file was read
        if (same_value(to_type(props_[k].type, *value), to_type(props_[k].type, old))) continue;
        const auto at = static_cast<std::size_t>(tok.data() - rest.data());
        out.append(rest.substr(copied, at - copied));
        append_value(out, props_[k].type, *value);
        copied = at + tok.size();
      }
    }
    out.append(rest.substr(copied));
    return out;
  }

  std::shared_ptr<const std::string> data_;  // the file, shared with read_mesh's buffer
  std::string name_;
  Encoding encoding_;
  std::size_t vertex_offset_;  // where the vertex element starts in data_
  std::size_t vertex_count_;
  std::vector<Property> props_;  // of the vertex element
  std::vector<Role> roles_;      // per vertex property: X..Z, NX..NZ or Skip
  bool has_normals_ = false;
  std::string kept_only_;
  std::size_t header_end_ = 0;  // where the body starts in data_
};

}  // namespace

std::shared_ptr<const FileSource> make_ply_source(std::shared_ptr<const std::string> data, const std::string& name,
                                                  const Header& header, const Layout& layout,
                                                  std::size_t vertex_offset) {
  return std::make_shared<PlySource>(std::move(data), name, header, layout, vertex_offset);
}

}  // namespace freeform::ply_detail
