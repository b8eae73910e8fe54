#include "freeform/edit/edit_json.h"

#include "freeform/bcm/boundary_band.h"
#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/io/file_util.h"
#include "freeform/regions/sel_file.h"
#include "freeform/regions/selectors.h"

#include <cmath>
#include <map>
#include <numbers>

namespace freeform {
namespace {

namespace fs = std::filesystem;

using json_messages::index_path;
using json_messages::key_path;
using json_messages::num;
using json_messages::quoted;
using json_messages::type_of;

// Rejects a 4x4 matrix that is not a finite, invertible affine map (message names `what`).
Eigen::Affine3d checked_matrix(const Eigen::Matrix4d& m, const std::string& what) {
  if (!m.allFinite()) throw InvalidInput(what + " has a non-finite entry");
  if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0)
    throw InvalidInput(what + ": the last row must be 0 0 0 1 (an affine map), got " + num(m(3, 0)) + " " +
                       num(m(3, 1)) + " " + num(m(3, 2)) + " " + num(m(3, 3)));
  try {
    return affine_from_matrix(m);
  } catch (const InvalidInput&) {  // the only check left: an invertible linear part
    const double det = m.topLeftCorner<3, 3>().determinant();
    if (!std::isfinite(det))  // entries near 1e300: their products overflow
      throw InvalidInput(what + " is too large for double precision (its determinant overflows); scale by less "
                                "than 1e100");
    throw InvalidInput(what + " is singular (determinant " + num(det) + "): it would flatten the handle");
  }
}

// The settings keys (kEditSettingsKeys) of an edit file or a session's parameters.
class SettingsReader : protected JsonReader {
 public:
  explicit SettingsReader(std::string name) : JsonReader(std::move(name)) {}

  // `j`'s settings keys; its other keys must be in `extra`. "smoothness.segments" is the caller's.
  EditSettings settings(const Json& j, std::span<const char* const> extra) const {
    if (!j.is_object()) fail("the edit must be a JSON object, got " + type_of(j));
    std::vector<const char*> allowed(kEditSettingsKeys.begin(), kEditSettingsKeys.end());
    allowed.insert(allowed.end(), extra.begin(), extra.end());
    keys(j, "", std::span<const char* const>(allowed));
    EditSettings e;
    if (j.contains("order")) {
      const long long k = integer(j["order"], "order");
      if (k < 1 || k > 3)
        fail("\"order\" must be 1 (membrane), 2 (thin plate) or 3 (minimal curvature variation), got " +
             std::to_string(k));
      e.settings.order = static_cast<int>(k);
    }
    if (j.contains("smoothness")) smoothness(j["smoothness"], e.settings);
    if (j.contains("anisotropic")) e.settings.anisotropic = boolean(j["anisotropic"], "anisotropic");
    if (j.contains("multiresolution")) e.multiresolution = boolean(j["multiresolution"], "multiresolution");
    if (j.contains("deformation")) e.deformation = deformation(j["deformation"]);
    if (j.contains("allow_unanchored")) e.allow_unanchored = boolean(j["allow_unanchored"], "allow_unanchored");
    if (j.contains("nonlinear")) nonlinear(j["nonlinear"], e.nonlinear);
    return e;
  }

 protected:
  double smoothness_value(const Json& j, const std::string& path, int k) const {
    const double c = number(j, path);
    if (c < 0.0 || c > k - 1)
      fail(quoted(path) + " must be in [0, " + std::to_string(k - 1) + "] for order " + std::to_string(k) +
           " (0 = crease, " + std::to_string(k - 1) + " = smoothest), got " + num(c));
    return c;
  }

 private:
  Deformation deformation(const Json& j) const {
    const std::string name = string(j, "deformation");
    if (const std::optional<Deformation> d = deformation_from_name(name)) return *d;
    std::string names;
    for (Deformation d : kDeformations)
      names += std::string(names.empty() ? "" : ", ") + "\"" + std::string(deformation_name(d)) + "\"";
    fail("\"deformation\" must be one of " + names + ", got \"" + name + "\"");
  }

  void nonlinear(const Json& j, NonlinearOptions& o) const {
    object(j, "nonlinear");
    keys(j, "nonlinear", {"max_iterations", "tolerance", "preserve_volume"});
    if (j.contains("max_iterations")) {
      const long long n = integer(j["max_iterations"], "nonlinear.max_iterations");
      if (n < 1 || n > 100000) fail("\"nonlinear.max_iterations\" must be in [1, 100000], got " + std::to_string(n));
      o.max_iterations = static_cast<int>(n);
    }
    if (j.contains("tolerance")) {
      const double t = number(j["tolerance"], "nonlinear.tolerance");
      if (!(t > 0.0 && t < 1.0)) fail("\"nonlinear.tolerance\" must be in (0, 1), got " + num(t));
      o.tolerance = t;
    }
    if (j.contains("preserve_volume")) o.preserve_volume = boolean(j["preserve_volume"], "nonlinear.preserve_volume");
  }

  void smoothness(const Json& j, BcmSettings& settings) const {
    object(j, "smoothness");
    keys(j, "smoothness", {"outer", "inner", "segments"});
    for (const char* side : {"outer", "inner"})
      if (j.contains(side))
        (std::string(side) == "outer" ? settings.smoothness.outer : settings.smoothness.inner) =
            smoothness_value(j[side], key_path("smoothness", side), settings.order);
  }
};

class Parser : SettingsReader {
 public:
  Parser(const Mesh& mesh, std::string name, fs::path base_dir)
      : SettingsReader(std::move(name)), mesh_(mesh), base_(std::move(base_dir)) {}

  Edit edit(const Json& j) {
    static constexpr std::array<const char*, 2> regions = {"support", "handles"};
    Edit e;
    static_cast<EditSettings&>(e) = settings(j, regions);
    e.support = selector(required(j, "", "support"), "support");
    if (j.contains("handles")) {
      const Json& hs = array(j["handles"], "handles");
      for (std::size_t i = 0; i < hs.size(); ++i) e.handles.push_back(handle(hs[i], index_path("handles", i)));
    }
    if (j.contains("smoothness") && j["smoothness"].contains("segments"))
      e.settings.smoothness.segments = segments(j["smoothness"]["segments"], e);
    return e;
  }

 private:
  const Mesh& mesh_;
  fs::path base_;
  std::map<std::string, std::vector<int>> sel_cache_;

  // Each segment keeps only the vertices where c acts (smoothness_band), so a segment that
  // selects none of them would silently do nothing: that is an error.
  std::vector<SmoothnessSegment> segments(const Json& j, const Edit& e) {
    const std::string path = "smoothness.segments";
    const Json& list = array(j, path);
    if (list.empty()) return {};
    std::vector<char> in_band(static_cast<std::size_t>(mesh_.n_vertices()), 0);
    try {
      for (Vertex v : smoothness_band(mesh_, edit_regions(mesh_, e), e.settings.order))
        in_band[static_cast<std::size_t>(v.idx())] = 1;
    } catch (const InvalidInput& err) {
      fail(quoted(path) + " cannot be placed: " + err.what());
    }
    const int k = e.settings.order;
    std::vector<SmoothnessSegment> out;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string p = index_path(path, i);
      object(list[i], p);
      keys(list[i], p, {"region", "value"});
      SmoothnessSegment seg;
      seg.value = smoothness_value(required(list[i], p, "value"), key_path(p, "value"), k);
      for (Vertex v : selector(required(list[i], p, "region"), key_path(p, "region")))
        if (in_band[static_cast<std::size_t>(v.idx())]) seg.vertices.push_back(v);
      if (seg.vertices.empty())
        fail(quoted(key_path(p, "region")) + " selects no constrained vertex where boundary smoothness acts " +
             (k == 1 ? std::string("(order 1 is always C0: there is nothing to set)")
                     : "(fixed or handle vertices within " + std::to_string(k - 1) + " ring" + (k > 2 ? "s" : "") +
                           " of the free region)"));
      out.push_back(std::move(seg));
    }
    return out;
  }

  std::vector<Vertex> selector(const Json& j, const std::string& path) {
    object(j, path);
    keys(j, path, {"vertices", "sphere", "geodesic", "sel", "labels"});
    int kinds = 0;
    for (const char* kind : {"vertices", "sphere", "geodesic", "sel"}) kinds += j.contains(kind) ? 1 : 0;
    if (kinds != 1)
      fail(quoted(path) + " must have exactly one of \"vertices\", \"sphere\", \"geodesic\", \"sel\"" +
           (kinds == 0 ? std::string(" (it has none)") : " (it has " + std::to_string(kinds) + ")"));
    const std::string who = name() + ": " + path;
    if (j.contains("labels") && !j.contains("sel"))
      fail(quoted(key_path(path, "labels")) + " is only allowed together with \"sel\"");
    if (j.contains("vertices")) {
      const std::string p = key_path(path, "vertices");
      const Json& list = j["vertices"];
      if (!list.is_array()) fail(quoted(p) + " must be an array of vertex indices, got " + type_of(list));
      std::vector<long long> ids;
      for (std::size_t i = 0; i < list.size(); ++i) ids.push_back(integer(list[i], index_path(p, i)));
      return select_indices(mesh_, ids, who);
    }
    for (const char* kind : {"sphere", "geodesic"}) {
      if (!j.contains(kind)) continue;
      const std::string p = key_path(path, kind);
      const Json& ball = j[kind];
      object(ball, p);
      keys(ball, p, {"center", "radius"});
      const Vec3 c = vec3(required(ball, p, "center"), key_path(p, "center"));
      const double r = number(required(ball, p, "radius"), key_path(p, "radius"));
      if (r <= 0.0) fail(quoted(key_path(p, "radius")) + " must be > 0, got " + num(r));
      return std::string(kind) == "sphere" ? select_sphere(mesh_, c, r, who) : select_geodesic(mesh_, c, r, who);
    }
    const std::string p = key_path(path, "sel");
    const fs::path file = fs::path(string(j["sel"], p));
    const Json& wanted_j = required(j, path, "labels");
    const std::string lp = key_path(path, "labels");
    if (!wanted_j.is_array() || wanted_j.empty()) fail(quoted(lp) + " must be a non-empty array of labels (0, 1, 2)");
    std::vector<int> wanted;
    for (std::size_t i = 0; i < wanted_j.size(); ++i) {
      const long long l = integer(wanted_j[i], index_path(lp, i));
      if (l < 0 || l > 2) fail(quoted(index_path(lp, i)) + " must be 0 (fixed), 1 (free) or 2 (handle), got " + std::to_string(l));
      wanted.push_back(static_cast<int>(l));
    }
    const std::string full = (file.is_absolute() ? file : base_ / file).string();
    auto it = sel_cache_.find(full);
    if (it == sel_cache_.end()) it = sel_cache_.emplace(full, read_sel_file(full, mesh_.n_vertices())).first;
    return select_labels(it->second, wanted, who);
  }

  // The file format keeps "fixed": true for an immovable handle.
  EditHandle handle(const Json& j, const std::string& path) {
    object(j, path);
    keys(j, path, {"region", "transform", "fixed"});
    EditHandle h;
    if (j.contains("fixed")) h.movable = !boolean(j["fixed"], key_path(path, "fixed"));
    if (!h.movable && j.contains("transform"))
      fail(quoted(path) + " is fixed and has a transform: a fixed handle does not move; remove one of them");
    h.vertices = selector(required(j, path, "region"), key_path(path, "region"));
    if (j.contains("transform")) transform(j["transform"], key_path(path, "transform"), h);
    return h;
  }

  void transform(const Json& j, const std::string& path, EditHandle& h) const {
    object(j, path);
    if (j.contains("matrix")) {
      keys(j, path, {"matrix"});
      const std::string p = key_path(path, "matrix");
      h.matrix = checked_matrix(matrix4(j["matrix"], p), name() + ": " + quoted(p));
      return;
    }
    keys(j, path, {"translate", "rotate", "scale", "pivot"});
    Manipulator& man = h.manipulator;
    if (j.contains("translate")) man.translation = vec3(j["translate"], key_path(path, "translate"));
    if (j.contains("pivot")) man.pivot = vec3(j["pivot"], key_path(path, "pivot"));
    if (j.contains("scale")) {
      const std::string p = key_path(path, "scale");
      man.scale = vec3(j["scale"], p);
      for (int i = 0; i < 3; ++i)
        if (std::abs(man.scale[i]) <= Manipulator::kMinScale)
          fail(quoted(index_path(p, static_cast<std::size_t>(i))) +
               (man.scale[i] == 0.0 ? std::string(" is 0: a zero scale flattens the handle (singular transform)")
                                    : " is " + num(man.scale[i]) +
                                          ", at most 1e-12 in size: it flattens the handle (numerically singular transform)"));
    }
    if (j.contains("rotate")) {
      const std::string p = key_path(path, "rotate");
      const Json& rot = j["rotate"];
      object(rot, p);
      keys(rot, p, {"axis", "degrees"});
      const Vec3 axis = vec3(required(rot, p, "axis"), key_path(p, "axis"));
      const double degrees = number(required(rot, p, "degrees"), key_path(p, "degrees"));
      if (axis == Vec3::Zero()) fail(quoted(key_path(p, "axis")) + " is the zero vector: a rotation needs an axis");
      man.rotation = Manipulator::axis_angle(axis, degrees);  // scale-safe normalization
    }
  }
};

Json vertex_selector(const std::vector<Vertex>& vs) {
  Json list = Json::array();
  for (Vertex v : vs) list.push_back(v.idx());
  return Json{{"vertices", std::move(list)}};
}

Json matrix_json(const Eigen::Affine3d& t) {
  Json rows = Json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({t.matrix()(r, 0), t.matrix()(r, 1), t.matrix()(r, 2), t.matrix()(r, 3)});
  rows.push_back({0.0, 0.0, 0.0, 1.0});  // exactly affine, as the parser demands
  return Json{{"matrix", std::move(rows)}};
}

}  // namespace

EditSettings parse_edit_settings(const Json& j, const std::string& name, std::span<const char* const> extra) {
  return SettingsReader(name).settings(j, extra);
}

Edit parse_edit(const Json& j, const Mesh& mesh, const std::string& name, const fs::path& base_dir) {
  return Parser(mesh, name, base_dir).edit(j);
}

Edit parse_edit_text(std::string_view text, const Mesh& mesh, const std::string& name, const fs::path& base_dir) {
  return parse_edit(parse_json_text(text, name), mesh, name, base_dir);
}

Edit read_edit_file(const std::string& path, const Mesh& mesh) {
  return parse_edit_text(read_file(path), mesh, path, fs::path(path).parent_path());
}

Edit edit_from_sel_def(const std::string& sel_path, const std::string& def_path, int order, const Mesh& mesh) {
  if (order < 1 || order > 3) throw InvalidInput("order must be 1, 2 or 3, got " + std::to_string(order));
  const std::vector<int> labels = read_sel_file(sel_path, mesh.n_vertices());
  const Eigen::Matrix4d m = read_def_file(def_path);
  Edit e;
  e.settings.order = order;
  const int support_labels[] = {kSelFree, kSelHandle};
  const int handle_label[] = {kSelHandle};
  e.support = select_labels(labels, support_labels, sel_path + ": the support (labels 1 and 2)");
  EditHandle h;
  h.vertices = select_labels(labels, handle_label, sel_path + ": the handle (label 2)");
  h.matrix = checked_matrix(m, def_path + ": the matrix");
  e.handles.push_back(std::move(h));
  return e;
}

Json edit_settings_to_json(const EditSettings& s) {
  Json j;
  j["order"] = s.settings.order;
  j["smoothness"] = Json{{"outer", resolved_outer(s.settings)}, {"inner", resolved_inner(s.settings)}};
  j["anisotropic"] = s.settings.anisotropic;
  j["multiresolution"] = s.multiresolution;
  j["deformation"] = deformation_name(s.deformation);
  if (s.allow_unanchored) j["allow_unanchored"] = true;
  if (s.deformation == Deformation::Nonlinear || s.nonlinear != NonlinearOptions{})
    j["nonlinear"] = Json{{"max_iterations", s.nonlinear.max_iterations},
                          {"tolerance", s.nonlinear.tolerance},
                          {"preserve_volume", s.nonlinear.preserve_volume}};
  return j;
}

Json edit_to_json(const Edit& edit) {
  Json j = edit_settings_to_json(edit);
  j["support"] = vertex_selector(edit.support);
  Json handles = Json::array();
  for (const EditHandle& h : edit.handles) {
    Json hj{{"region", vertex_selector(h.vertices)}};
    if (!h.movable) {
      hj["fixed"] = true;
    } else if (h.matrix) {
      hj["transform"] = matrix_json(*h.matrix);
    } else if (h.manipulator.pivot) {
      hj["transform"] = matrix_json(h.manipulator.to_affine(*h.manipulator.pivot));
    } else if (!is_identity(h.manipulator)) {
      const Manipulator& m = h.manipulator;
      const Eigen::AngleAxisd aa(m.rotation.normalized());
      hj["transform"] = Json{{"translate", {m.translation.x(), m.translation.y(), m.translation.z()}},
                             {"rotate", {{"axis", {aa.axis().x(), aa.axis().y(), aa.axis().z()}},
                                         {"degrees", aa.angle() * 180.0 / std::numbers::pi}}},
                             {"scale", {m.scale.x(), m.scale.y(), m.scale.z()}}};
    }
    handles.push_back(std::move(hj));
  }
  j["handles"] = std::move(handles);
  if (!edit.settings.smoothness.segments.empty()) {
    Json segs = Json::array();
    for (const SmoothnessSegment& seg : edit.settings.smoothness.segments)
      segs.push_back(Json{{"region", vertex_selector(seg.vertices)}, {"value", seg.value}});
    j["smoothness"]["segments"] = std::move(segs);
  }
  return j;
}

void write_edit_file(const std::string& path, const Edit& edit) { write_file_atomic(path, json_text(edit_to_json(edit))); }

}  // namespace freeform
