// The roles of the PLY vertex and face properties: positions, vertex indices and, as
// attributes, normals, texture coordinates, colours and every other scalar property
// (ply_layout.h).
#include "freeform/io/ply_layout.h"

#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <array>
#include <optional>
#include <span>

namespace freeform::ply_detail {
namespace {

using io_detail::fail;

// The k-th role of a run: X, Y, Z or NX, NY, NZ.
Role nth_role(Role first, std::size_t k) { return static_cast<Role>(static_cast<int>(first) + static_cast<int>(k)); }

// Finds the 'vertex' and 'face' elements.
void find_elements(const Header& header, const std::string& name, Layout& layout) {
  std::optional<std::size_t> vertex;
  std::optional<std::size_t> face;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& el = header.elements[e];
    if (el.name == "vertex") {
      if (vertex) fail(name, 0, "PLY header has more than one 'vertex' element");
      vertex = e;
    } else if (el.name == "face") {
      if (face) fail(name, 0, "PLY header has more than one 'face' element");
      face = e;
    }
  }
  if (!vertex) fail(name, 0, "PLY header has no 'vertex' element" + header.skipped_hint());
  if (!face) fail(name, 0, "no faces (PLY header has no 'face' element)" + header.skipped_hint());
  layout.vertex_element = *vertex;
  layout.face_element = *face;
}

// Marks the vertex element's x, y, z as positions.
void bind_positions(const Element& v, const std::string& name, std::vector<Field>& fields) {
  for (std::size_t k = 0; k < kPositionNames.size(); ++k) {
    const std::string_view axis = kPositionNames[k];
    bool found = false;
    for (std::size_t p = 0; p < v.props.size(); ++p) {
      if (v.props[p].name != axis) continue;
      if (v.props[p].is_list) fail(name, 0, fmt::format("vertex property '{}' is a list, expected a scalar", axis));
      if (found) fail(name, 0, fmt::format("vertex element has two '{}' properties", axis));
      fields[p].role = nth_role(Role::X, k);
      found = true;
    }
    if (!found) fail(name, 0, fmt::format("vertex element has no '{}' property", axis));
  }
}

// Marks the face element's vertex_indices (or vertex_index) list as the vertex indices.
void bind_indices(const Element& f, const std::string& name, std::vector<Field>& fields) {
  bool found = false;
  for (std::size_t p = 0; p < f.props.size(); ++p) {
    if (f.props[p].name != "vertex_indices" && f.props[p].name != "vertex_index") continue;
    if (found) fail(name, 0, "face element has both 'vertex_indices' and 'vertex_index'");
    if (!f.props[p].is_list) fail(name, 0, fmt::format("face property '{}' must be a list", f.props[p].name));
    if (!is_integer(f.props[p].type))
      fail(name, 0, fmt::format("face property '{}' must have an integer item type", f.props[p].name));
    fields[p].role = Role::Indices;
    found = true;
  }
  if (!found) fail(name, 0, "face element has no 'vertex_indices' (or 'vertex_index') list property");
}

// The first scalar property named `name` that no role claims yet, or -1.
int find_free_scalar(const Element& el, const std::vector<Field>& fields, std::string_view name) {
  for (std::size_t p = 0; p < el.props.size(); ++p)
    if (!el.props[p].is_list && fields[p].role == Role::Skip && el.props[p].name == name) return static_cast<int>(p);
  return -1;
}

enum class Group { Normal, Uv, Color };

// Binds the leading properties of `names` (at least `required` of them, else none) as the
// components of target `target`; returns how many were bound. Normals get the roles NX..NZ.
int bind_group(const Element& el, std::vector<Field>& fields, std::span<const std::string_view> names,
               std::size_t required, Group group, int target) {
  std::array<int, 4> found{};
  std::size_t n = 0;
  for (; n < names.size(); ++n) {
    found[n] = find_free_scalar(el, fields, names[n]);
    if (found[n] < 0) break;
  }
  if (n < required) return 0;
  for (std::size_t k = 0; k < n; ++k) {
    Field& f = fields[static_cast<std::size_t>(found[k])];
    f.role = group == Group::Normal ? nth_role(Role::NX, k) : Role::Attribute;
    f.target = target;
    f.component = static_cast<int>(k);
    const Scalar type = el.props[static_cast<std::size_t>(found[k])].type;
    if (group == Group::Color && is_integer(type)) f.scale = 1 / integer_max(type);
  }
  return static_cast<int>(n);
}

// The colour and every scalar property no role claims, as named attributes of the element.
void bind_named(const Element& el, std::vector<Field>& fields, std::vector<Target>& targets,
                std::vector<NamedAttribute>& named) {
  const int base = static_cast<int>(targets.size());
  const std::size_t first = named.size();
  for (const auto& names : kColorNames) {
    const int width = bind_group(el, fields, names, 3, Group::Color, base);
    if (width == 0) continue;
    named.push_back({"color", width, {}});
    break;
  }
  for (std::size_t p = 0; p < el.props.size(); ++p) {
    if (el.props[p].is_list || fields[p].role != Role::Skip) continue;
    fields[p] = {Role::Attribute, base + static_cast<int>(named.size() - first), 0, 1};
    named.push_back({el.props[p].name, 1, {}});
  }
  // Pointers are taken once `named` has stopped growing.
  for (std::size_t i = first; i < named.size(); ++i) targets.push_back({&named[i].values, named[i].width});
}

}  // namespace

Layout make_layout(const Header& header, const std::string& name) {
  Layout layout;
  layout.fields.resize(header.elements.size());
  layout.targets.resize(header.elements.size());
  for (std::size_t e = 0; e < header.elements.size(); ++e)
    layout.fields[e].assign(header.elements[e].props.size(), Field{});
  find_elements(header, name, layout);
  const Element& v = header.elements[layout.vertex_element];
  const Element& f = header.elements[layout.face_element];
  bind_positions(v, name, layout.fields[layout.vertex_element]);
  bind_indices(f, name, layout.fields[layout.face_element]);

  layout.vertex_count = v.count;
  if (v.count == 0) fail(name, 0, "no vertices (vertex element count is 0)");
  if (f.count == 0) fail(name, 0, "no faces (face element count is 0)");
  if (v.count > io_detail::kMaxElements) fail(name, 0, fmt::format("vertex count {} is too large", v.count));
  if (f.count > io_detail::kMaxElements) fail(name, 0, fmt::format("face count {} is too large", f.count));
  return layout;
}

void bind_attributes(const Header& header, Layout& layout, MeshAttributes& attributes) {
  const std::size_t ve = layout.vertex_element;
  const Element& v = header.elements[ve];
  std::vector<Target>& targets = layout.targets[ve];
  if (bind_group(v, layout.fields[ve], kNormalNames, 3, Group::Normal, static_cast<int>(targets.size())) == 3) {
    attributes.normal.width = 3;
    targets.push_back({&attributes.normal.values, 3});
  }
  for (const auto& names : kUvNames) {
    if (bind_group(v, layout.fields[ve], names, 2, Group::Uv, static_cast<int>(targets.size())) == 0) continue;
    attributes.uv.width = 2;
    targets.push_back({&attributes.uv.values, 2});
    break;
  }
  bind_named(v, layout.fields[ve], targets, attributes.vertex);
  const std::size_t fe = layout.face_element;
  bind_named(header.elements[fe], layout.fields[fe], layout.targets[fe], attributes.face);
}

}  // namespace freeform::ply_detail
