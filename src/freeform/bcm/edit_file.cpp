#include "freeform/bcm/edit_file.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/io/file_util.h"
#include "freeform/regions/sel_file.h"
#include "freeform/regions/selectors.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <initializer_list>
#include <map>
#include <numbers>
#include <sstream>

namespace freeform {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

using json_messages::index_path;
using json_messages::key_path;
using json_messages::num;
using json_messages::quoted;
using json_messages::type_of;

// Rejects a 4x4 matrix that is not a finite, invertible affine map (message names `what`).
void check_matrix(const Eigen::Matrix4d& m, const std::string& what) {
  if (!m.allFinite()) throw InvalidInput(what + " has a non-finite entry");
  if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0)
    throw InvalidInput(what + ": the last row must be 0 0 0 1 (an affine map), got " + num(m(3, 0)) + " " +
                       num(m(3, 1)) + " " + num(m(3, 2)) + " " + num(m(3, 3)));
  const Eigen::Matrix3d a = m.topLeftCorner<3, 3>();
  const double s = a.cwiseAbs().maxCoeff();
  const double det = a.determinant();
  if (!(s > 0.0) || !std::isfinite(det) || std::abs(det) <= 1e-12 * s * s * s)
    throw InvalidInput(what + " is singular (determinant " + num(det) + "): it would flatten the handle");
}

class Parser {
 public:
  Parser(const Mesh& mesh, std::string name, fs::path base_dir)
      : mesh_(mesh), name_(std::move(name)), base_(std::move(base_dir)) {}

  Edit edit(const json& j) {
    if (!j.is_object()) fail("the edit must be a JSON object, got " + type_of(j));
    keys(j, "", {"order", "support", "handles", "smoothness", "anisotropic", "multiresolution"});
    Edit e;
    if (j.contains("order")) {
      const long long k = integer(j["order"], "order");
      if (k < 1 || k > 3)
        fail("\"order\" must be 1 (membrane), 2 (thin plate) or 3 (minimal curvature variation), got " +
             std::to_string(k));
      e.settings.order = static_cast<int>(k);
    }
    if (j.contains("smoothness")) smoothness(j["smoothness"], e.settings);
    if (j.contains("anisotropic")) e.anisotropic = boolean(j["anisotropic"], "anisotropic");
    if (j.contains("multiresolution")) e.multiresolution = boolean(j["multiresolution"], "multiresolution");
    e.support = selector(required(j, "", "support"), "support");
    if (j.contains("handles")) {
      const json& hs = j["handles"];
      if (!hs.is_array()) fail(quoted("handles") + " must be an array of handles, got " + type_of(hs));
      for (std::size_t i = 0; i < hs.size(); ++i) e.handles.push_back(handle(hs[i], index_path("handles", i)));
    }
    return e;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw InvalidInput(name_ + ": " + message); }

  const json& required(const json& obj, const std::string& path, const char* key) const {
    if (!obj.contains(key)) fail("missing required key " + quoted(key_path(path, key)));
    return obj[key];
  }

  void keys(const json& obj, const std::string& path, std::initializer_list<const char*> allowed) const {
    for (const auto& [key, value] : obj.items()) {
      if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }) != allowed.end())
        continue;
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + "\"" + a + "\"";
      fail("unknown key " + quoted(key_path(path, key)) + " (allowed here: " + list + ")");
    }
  }

  void object(const json& j, const std::string& path) const {
    if (!j.is_object()) fail(quoted(path) + " must be an object, got " + type_of(j));
  }

  long long integer(const json& j, const std::string& path) const {
    if (j.is_number_unsigned())
      return static_cast<long long>(std::min<unsigned long long>(j.get<unsigned long long>(), LLONG_MAX));
    if (!j.is_number_integer()) fail(quoted(path) + " must be an integer, got " + type_of(j));
    return j.get<long long>();
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(quoted(path) + " must be a number, got " + type_of(j));
    const double x = j.get<double>();
    if (!std::isfinite(x)) fail(quoted(path) + " must be finite");
    return x;
  }

  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(quoted(path) + " must be true or false, got " + type_of(j));
    return j.get<bool>();
  }

  Vec3 vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(quoted(path) + " must be an array of 3 numbers [x, y, z]");
    return {number(j[0], index_path(path, 0)), number(j[1], index_path(path, 1)), number(j[2], index_path(path, 2))};
  }

  void smoothness(const json& j, BcmSettings& settings) const {
    object(j, "smoothness");
    keys(j, "smoothness", {"outer", "inner"});
    const int k = settings.order;
    for (const char* side : {"outer", "inner"}) {
      if (!j.contains(side)) continue;
      const std::string path = key_path("smoothness", side);
      const double c = number(j[side], path);
      if (c < 0.0 || c > k - 1)
        fail(quoted(path) + " must be in [0, " + std::to_string(k - 1) + "] for order " + std::to_string(k) +
             " (0 = crease, " + std::to_string(k - 1) + " = smoothest), got " + num(c));
      (std::string(side) == "outer" ? settings.smoothness.outer : settings.smoothness.inner) = c;
    }
  }

  std::vector<Vertex> selector(const json& j, const std::string& path) {
    object(j, path);
    keys(j, path, {"vertices", "sphere", "geodesic", "sel", "labels"});
    int kinds = 0;
    for (const char* kind : {"vertices", "sphere", "geodesic", "sel"}) kinds += j.contains(kind) ? 1 : 0;
    if (kinds != 1)
      fail(quoted(path) + " must have exactly one of \"vertices\", \"sphere\", \"geodesic\", \"sel\"" +
           (kinds == 0 ? std::string(" (it has none)") : " (it has " + std::to_string(kinds) + ")"));
    const std::string who = name_ + ": " + path;
    if (j.contains("labels") && !j.contains("sel"))
      fail(quoted(key_path(path, "labels")) + " is only allowed together with \"sel\"");
    if (j.contains("vertices")) {
      const std::string p = key_path(path, "vertices");
      const json& list = j["vertices"];
      if (!list.is_array()) fail(quoted(p) + " must be an array of vertex indices, got " + type_of(list));
      std::vector<long long> ids;
      for (std::size_t i = 0; i < list.size(); ++i) ids.push_back(integer(list[i], index_path(p, i)));
      return select_indices(mesh_, ids, who);
    }
    for (const char* kind : {"sphere", "geodesic"}) {
      if (!j.contains(kind)) continue;
      const std::string p = key_path(path, kind);
      const json& ball = j[kind];
      object(ball, p);
      keys(ball, p, {"center", "radius"});
      const Vec3 c = vec3(required(ball, p, "center"), key_path(p, "center"));
      const double r = number(required(ball, p, "radius"), key_path(p, "radius"));
      if (r <= 0.0) fail(quoted(key_path(p, "radius")) + " must be > 0, got " + num(r));
      return std::string(kind) == "sphere" ? select_sphere(mesh_, c, r, who) : select_geodesic(mesh_, c, r, who);
    }
    const std::string p = key_path(path, "sel");
    if (!j["sel"].is_string()) fail(quoted(p) + " must be a file name (string), got " + type_of(j["sel"]));
    const json& wanted_j = required(j, path, "labels");
    const std::string lp = key_path(path, "labels");
    if (!wanted_j.is_array() || wanted_j.empty()) fail(quoted(lp) + " must be a non-empty array of labels (0, 1, 2)");
    std::vector<int> wanted;
    for (std::size_t i = 0; i < wanted_j.size(); ++i) {
      const long long l = integer(wanted_j[i], index_path(lp, i));
      if (l < 0 || l > 2) fail(quoted(index_path(lp, i)) + " must be 0 (fixed), 1 (free) or 2 (handle), got " + std::to_string(l));
      wanted.push_back(static_cast<int>(l));
    }
    const fs::path file = fs::path(j["sel"].get<std::string>());
    const std::string full = (file.is_absolute() ? file : base_ / file).string();
    auto it = sel_cache_.find(full);
    if (it == sel_cache_.end()) it = sel_cache_.emplace(full, read_sel_file(full, mesh_.n_vertices())).first;
    return select_labels(it->second, wanted, who);
  }

  EditHandle handle(const json& j, const std::string& path) {
    object(j, path);
    keys(j, path, {"region", "transform", "fixed"});
    EditHandle h;
    if (j.contains("fixed")) h.fixed = boolean(j["fixed"], key_path(path, "fixed"));
    if (h.fixed && j.contains("transform"))
      fail(quoted(path) + " is fixed and has a transform: a fixed handle does not move; remove one of them");
    h.vertices = selector(required(j, path, "region"), key_path(path, "region"));
    if (j.contains("transform")) transform(j["transform"], key_path(path, "transform"), h);
    return h;
  }

  void transform(const json& j, const std::string& path, EditHandle& h) const {
    object(j, path);
    if (j.contains("matrix")) {
      keys(j, path, {"matrix"});
      const std::string p = key_path(path, "matrix");
      const json& rows = j["matrix"];
      if (!rows.is_array() || rows.size() != 4) fail(quoted(p) + " must be 4 rows of 4 numbers (row-major)");
      Eigen::Matrix4d m;
      for (std::size_t r = 0; r < 4; ++r) {
        const std::string rp = index_path(p, r);
        if (!rows[r].is_array() || rows[r].size() != 4) fail(quoted(rp) + " must be a row of 4 numbers");
        for (std::size_t c = 0; c < 4; ++c)
          m(static_cast<int>(r), static_cast<int>(c)) = number(rows[r][c], index_path(rp, c));
      }
      check_matrix(m, name_ + ": " + quoted(p));
      h.matrix = Eigen::Affine3d(m);
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
        if (std::abs(man.scale[i]) <= 1e-12)
          fail(quoted(index_path(p, static_cast<std::size_t>(i))) + " is 0: a zero scale flattens the handle (singular transform)");
    }
    if (j.contains("rotate")) {
      const std::string p = key_path(path, "rotate");
      const json& rot = j["rotate"];
      object(rot, p);
      keys(rot, p, {"axis", "degrees"});
      const Vec3 axis = vec3(required(rot, p, "axis"), key_path(p, "axis"));
      const double degrees = number(required(rot, p, "degrees"), key_path(p, "degrees"));
      if (!(axis.norm() > 0.0)) fail(quoted(key_path(p, "axis")) + " is the zero vector: a rotation needs an axis");
      man.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()));
    }
  }

  const Mesh& mesh_;
  std::string name_;
  fs::path base_;
  std::map<std::string, std::vector<int>> sel_cache_;
};

// 1-based line and column of byte offset `pos` in `text`.
std::pair<std::size_t, std::size_t> line_column(std::string_view text, std::size_t pos) {
  pos = std::min(pos, text.size());
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < pos; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

}  // namespace

Edit parse_edit(const nlohmann::json& j, const Mesh& mesh, const std::string& name, const fs::path& base_dir) {
  return Parser(mesh, name, base_dir).edit(j);
}

Edit parse_edit_text(std::string_view text, const Mesh& mesh, const std::string& name, const fs::path& base_dir) {
  json j;
  // nlohmann keeps the last of repeated keys silently; a strict parser refuses them.
  std::vector<std::vector<std::string>> seen;  // keys of each open object
  std::string duplicate;
  const json::parser_callback_t check_duplicates = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) seen.emplace_back();
    if (event == json::parse_event_t::object_end && !seen.empty()) seen.pop_back();
    if (event == json::parse_event_t::key && !seen.empty() && duplicate.empty()) {
      const std::string key = parsed.get<std::string>();
      if (std::find(seen.back().begin(), seen.back().end(), key) != seen.back().end()) duplicate = key;
      seen.back().push_back(key);
    }
    return true;
  };
  try {
    j = json::parse(text, check_duplicates);
  } catch (const json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character.
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string reason = e.what();
    const std::size_t colon = reason.find(": ", reason.find("parse error"));
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    throw IoError(name, line, "malformed JSON at column " + std::to_string(col) + ": " + reason);
  } catch (const json::exception& e) {  // e.g. a number too large for a double
    std::string reason = e.what();
    const std::size_t bracket = reason.find("] ");
    if (bracket != std::string::npos) reason = reason.substr(bracket + 2);
    throw IoError(name, 0, "malformed JSON: " + reason);
  }
  if (!duplicate.empty()) throw InvalidInput(name + ": the key \"" + duplicate + "\" appears twice in one object");
  return parse_edit(j, mesh, name, base_dir);
}

Edit read_edit_file(const std::string& path, const Mesh& mesh) {
  return parse_edit_text(read_file(path), mesh, path, fs::path(path).parent_path());
}

Edit edit_from_sel_def(const std::string& sel_path, const std::string& def_path, int order, const Mesh& mesh) {
  if (order < 1 || order > 3) throw InvalidInput("order must be 1, 2 or 3, got " + std::to_string(order));
  const std::vector<int> labels = read_sel_file(sel_path, mesh.n_vertices());
  const Eigen::Matrix4d m = read_def_file(def_path);
  check_matrix(m, def_path + ": the matrix");
  Edit e;
  e.settings.order = order;
  const int support_labels[] = {kSelFree, kSelHandle};
  const int handle_label[] = {kSelHandle};
  e.support = select_labels(labels, support_labels, sel_path + ": the support (labels 1 and 2)");
  EditHandle h;
  h.vertices = select_labels(labels, handle_label, sel_path + ": the handle (label 2)");
  h.matrix = Eigen::Affine3d(m);
  e.handles.push_back(std::move(h));
  return e;
}

void check_edit_available(const Edit& /*edit*/) {
  // Everything an edit file can express is available (anisotropic, multiresolution).
}

Regions edit_regions(const Mesh& mesh, const Edit& edit) {
  std::vector<HandleRegion> handles;
  handles.reserve(edit.handles.size());
  for (const EditHandle& h : edit.handles) handles.push_back(HandleRegion{h.vertices, !h.fixed});
  return Regions(mesh, edit.support, std::move(handles));
}

}  // namespace freeform
