#include "editor/edit_state.h"

#include "freeform/bcm/boundary_band.h"
#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>

namespace freeform::editor {
namespace {

bool same_opt_vec(const std::optional<Vec3>& a, const std::optional<Vec3>& b) {
  return a.has_value() == b.has_value() && (!a || *a == *b);
}

Eigen::Matrix3d linear_part(const Manipulator& m) {
  const double qn = m.rotation.norm();
  return Eigen::Quaterniond(m.rotation.coeffs() / qn).toRotationMatrix() * m.scale.asDiagonal();
}

}  // namespace

EditParameters::EditParameters() {
  settings.order = 3;
  settings.smoothness.outer = settings.smoothness.inner = 2.0;
}

EditParameters normalized(EditParameters p) {
  BcmSettings& b = p.settings;
  if (b.order < 1 || b.order > 3)
    throw InvalidInput("order must be 1 (membrane), 2 (thin plate) or 3 (minimal curvature variation), got " +
                       std::to_string(b.order));
  if (!std::isfinite(b.smoothness.outer) || !std::isfinite(b.smoothness.inner))
    throw InvalidInput("smoothness must be a finite number");
  const double top = b.order - 1.0;
  // The library's "default" (k - 1) written out: the panel's sliders show numbers.
  if (b.smoothness.outer == Smoothness::kDefault) b.smoothness.outer = top;
  if (b.smoothness.inner == Smoothness::kDefault) b.smoothness.inner = top;
  b.smoothness.outer = std::clamp(b.smoothness.outer, 0.0, top);
  b.smoothness.inner = std::clamp(b.smoothness.inner, 0.0, top);
  for (SmoothnessSegment& s : b.smoothness.segments) {
    if (!std::isfinite(s.value)) throw InvalidInput("segment smoothness must be a finite number");
    s.value = std::clamp(s.value, 0.0, top);
  }
  return p;
}

Eigen::Affine3d HandleState::transform(const Vec3& default_pivot) const {
  const Eigen::Affine3d m = manipulator.to_affine(default_pivot);  // validates
  if (!matrix) return m;
  if (is_identity(manipulator)) return *matrix;
  Eigen::Affine3d t = m * *matrix;
  t.matrix().row(3) << 0, 0, 0, 1;
  return t;
}

bool same_transform(const HandleState& a, const HandleState& b) {
  const Manipulator& x = a.manipulator;
  const Manipulator& y = b.manipulator;
  if (!(x.translation == y.translation && x.rotation.coeffs() == y.rotation.coeffs() && x.scale == y.scale &&
        same_opt_vec(x.pivot, y.pivot)))
    return false;
  return a.matrix.has_value() == b.matrix.has_value() && (!a.matrix || a.matrix->matrix() == b.matrix->matrix());
}

bool operator==(const HandleState& a, const HandleState& b) {
  return a.id == b.id && a.movable == b.movable && same_transform(a, b);
}

Manipulator recentred(const Manipulator& m, const Vec3& pivot) {
  Manipulator r = m;
  r.pivot = pivot;
  if (!m.pivot) return r;
  // p + A(x - p) + t == p' + A(x - p') + t'  =>  t' = (I - A)(p - p') + t
  const Eigen::Matrix3d a = linear_part(m);
  r.translation = (Eigen::Matrix3d::Identity() - a) * (*m.pivot - pivot) + m.translation;
  return r;
}

Vec3 centroid(const Mesh& rest, const std::vector<Vertex>& vertices) {
  Vec3 c = Vec3::Zero();
  if (vertices.empty()) return c;
  for (Vertex v : vertices) c += rest.position(v);
  c /= static_cast<double>(vertices.size());
  return c;
}

EditState::EditState(int n_vertices)
    : support_(static_cast<std::size_t>(n_vertices), 0), handle_(static_cast<std::size_t>(n_vertices), -1) {}

const HandleState* EditState::find_handle(int id) const {
  const int i = handle_index(id);
  return i < 0 ? nullptr : &handles_[static_cast<std::size_t>(i)];
}

int EditState::handle_index(int id) const {
  for (std::size_t i = 0; i < handles_.size(); ++i)
    if (handles_[i].id == id) return static_cast<int>(i);
  return -1;
}

std::vector<Vertex> EditState::handle_vertices(int id) const {
  std::vector<Vertex> out;
  for (std::size_t v = 0; v < handle_.size(); ++v)
    if (handle_[v] == id) out.emplace_back(static_cast<int>(v));
  return out;
}

int EditState::handle_size(int id) const {
  const int i = handle_index(id);
  return i < 0 ? 0 : counts_[static_cast<std::size_t>(i)];
}

void EditState::check_vertex(Vertex v) const {
  if (v.idx() < 0 || v.idx() >= n_vertices())
    throw InvalidInput("vertex " + std::to_string(v.idx()) + " is outside the mesh, which has vertices 0.." +
                       std::to_string(n_vertices() - 1));
}

void EditState::set_vertex(Vertex v, bool support, int handle_id) {
  check_vertex(v);
  const int new_index = handle_id < 0 ? -1 : handle_index(handle_id);
  if (handle_id >= 0 && new_index < 0) throw InvalidInput("there is no handle " + std::to_string(handle_id));
  const auto i = static_cast<std::size_t>(v.idx());
  const int old_id = handle_[i];
  n_support_ -= in_support(v) ? 1 : 0;
  if (old_id >= 0) {
    --counts_[static_cast<std::size_t>(handle_index(old_id))];
    --n_handle_vertices_;
  }
  support_[i] = support ? 1 : 0;
  handle_[i] = handle_id < 0 ? -1 : handle_id;
  if (new_index >= 0) {
    ++counts_[static_cast<std::size_t>(new_index)];
    ++n_handle_vertices_;
  }
  n_support_ += in_support(v) ? 1 : 0;
}

void EditState::insert_handle(int index, HandleState h) {
  if (index < 0 || index > static_cast<int>(handles_.size()))
    throw InvalidInput("handle position " + std::to_string(index) + " is out of range");
  if (h.id < 0 || handle_index(h.id) >= 0) throw InvalidInput("handle id " + std::to_string(h.id) + " is taken or negative");
  next_id_ = std::max(next_id_, h.id + 1);
  handles_.insert(handles_.begin() + index, std::move(h));
  counts_.insert(counts_.begin() + index, 0);
}

HandleState EditState::erase_handle(int id) {
  const int i = handle_index(id);
  if (i < 0) throw InvalidInput("there is no handle " + std::to_string(id));
  if (counts_[static_cast<std::size_t>(i)] != 0)
    throw InvalidInput("handle " + std::to_string(id) + " still has vertices; clear them before removing it");
  HandleState h = std::move(handles_[static_cast<std::size_t>(i)]);
  handles_.erase(handles_.begin() + i);
  counts_.erase(counts_.begin() + i);
  return h;
}

void EditState::set_parameters(const EditParameters& p) { params_ = normalized(p); }

void EditState::set_transform(int id, const Manipulator& m, const std::optional<Eigen::Affine3d>& matrix) {
  const int i = handle_index(id);
  if (i < 0) throw InvalidInput("there is no handle " + std::to_string(id));
  if (matrix) affine_from_matrix(matrix->matrix());  // throws InvalidInput for a singular map
  HandleState& h = handles_[static_cast<std::size_t>(i)];
  HandleState next{h.id, h.movable, m, matrix};
  (void)next.transform();  // throws InvalidInput before anything changes
  h = std::move(next);
}

std::vector<Vertex> EditState::support_vertices() const {
  std::vector<Vertex> out;
  out.reserve(static_cast<std::size_t>(n_support_));
  for (std::size_t v = 0; v < handle_.size(); ++v)
    if (support_[v] != 0 || handle_[v] >= 0) out.emplace_back(static_cast<int>(v));
  return out;
}

Eigen::Affine3d EditState::transform(int id, const Mesh& rest) const {
  const HandleState* h = find_handle(id);
  if (!h) throw InvalidInput("there is no handle " + std::to_string(id));
  return h->manipulator.pivot ? h->transform() : h->transform(centroid(rest, handle_vertices(id)));
}

std::string EditState::problem(const Mesh& rest) const {
  if (rest.n_vertices() != n_vertices())
    return "the regions were painted on a mesh with " + std::to_string(n_vertices()) + " vertices, this one has " +
           std::to_string(rest.n_vertices());
  if (n_support_ == 0) return "paint a support region: the part of the surface that may change";
  for (std::size_t i = 0; i < handles_.size(); ++i)
    if (counts_[i] == 0) return "handle " + std::to_string(handles_[i].id) + " has no vertices: paint it or delete it";
  if (n_free() == 0) return "the support is all handle: paint free support around the handles";
  try {
    (void)regions(rest);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return {};
}

Regions EditState::regions(const Mesh& rest) const {
  std::vector<HandleRegion> hs;
  for (const HandleState& h : handles_) hs.push_back(HandleRegion{handle_vertices(h.id), h.movable});
  return Regions(rest, support_vertices(), std::move(hs));
}

Edit EditState::to_edit(const Mesh& rest) const {
  Edit e;
  static_cast<EditSettings&>(e) = params_;
  e.support = support_vertices();
  for (const HandleState& h : handles_) {
    EditHandle eh;
    eh.vertices = handle_vertices(h.id);
    eh.movable = h.movable;
    if (h.movable) eh.matrix = h.manipulator.pivot ? h.transform() : h.transform(centroid(rest, eh.vertices));
    e.handles.push_back(std::move(eh));
  }
  auto& segments = e.settings.smoothness.segments;
  if (!segments.empty() && problem(rest).empty()) {
    std::vector<char> in_band(static_cast<std::size_t>(n_vertices()), 0);
    for (Vertex v : smoothness_band(rest, regions(rest), params_.settings.order)) in_band[static_cast<std::size_t>(v.idx())] = 1;
    for (SmoothnessSegment& seg : segments)
      std::erase_if(seg.vertices, [&](Vertex v) { return !in_band[static_cast<std::size_t>(v.idx())]; });
    std::erase_if(segments, [](const SmoothnessSegment& seg) { return seg.vertices.empty(); });
  }
  return e;
}

EditState EditState::from_edit(const Edit& edit, const Mesh& rest, int first_id) {
  EditState s(rest.n_vertices());
  EditParameters p;
  static_cast<EditSettings&>(p) = edit;
  for (const SmoothnessSegment& seg : p.settings.smoothness.segments)
    for (Vertex v : seg.vertices) s.check_vertex(v);
  s.set_parameters(p);
  for (Vertex v : edit.support) s.set_vertex(v, true, -1);
  for (std::size_t i = 0; i < edit.handles.size(); ++i) {
    const EditHandle& eh = edit.handles[i];
    HandleState h;
    h.id = first_id + static_cast<int>(i);
    h.movable = eh.movable;
    s.insert_handle(static_cast<int>(i), h);
    std::vector<Vertex> vs;
    for (Vertex v : eh.vertices) {
      s.check_vertex(v);
      const int other = s.handle_of(v);
      if (other == h.id) continue;  // duplicates are ignored, as in selectors
      if (other >= 0)
        throw InvalidInput("vertex " + std::to_string(v.idx()) + " is in handles " + std::to_string(other - first_id) +
                           " and " + std::to_string(i) + ": handles must not overlap");
      s.set_vertex(v, s.support_flag(v), h.id);
      vs.push_back(v);
    }
    std::sort(vs.begin(), vs.end());
    Manipulator m = h.movable && !eh.matrix ? eh.manipulator : Manipulator{};
    if (!m.pivot) m.pivot = centroid(rest, vs);
    s.set_transform(h.id, m, h.movable ? eh.matrix : std::nullopt);
  }
  return s;
}

bool EditState::operator==(const EditState& o) const {
  return support_ == o.support_ && handle_ == o.handle_ && handles_ == o.handles_ && params_ == o.params_;
}

}  // namespace freeform::editor
