#include "editor/session.h"

#include "freeform/bcm/edit_file.h"
#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <sstream>

namespace freeform::editor {
namespace {

using ojson = nlohmann::ordered_json;
namespace fs = std::filesystem;

using json_messages::num;
using json_messages::type_of;
std::string at(const std::string& parent, const std::string& key) { return json_messages::key_path(parent, key); }
std::string at(const std::string& parent, std::size_t i) { return json_messages::index_path(parent, i); }
std::string q(const std::string& path) { return json_messages::quoted(path); }

ojson vec_json(const Vec3& v) { return ojson::array({v.x(), v.y(), v.z()}); }

ojson handle_json(const HandleState& h, const std::vector<Vertex>& vertices) {
  ojson vs = ojson::array();
  for (Vertex v : vertices) vs.push_back(v.idx());
  const Manipulator& m = h.manipulator;
  ojson mj{{"translation", vec_json(m.translation)},
           {"rotation", ojson::array({m.rotation.w(), m.rotation.x(), m.rotation.y(), m.rotation.z()})},
           {"scale", vec_json(m.scale)}};
  if (m.pivot) mj["pivot"] = vec_json(*m.pivot);
  ojson j{{"id", h.id}, {"movable", h.movable}, {"vertices", std::move(vs)}, {"manipulator", std::move(mj)}};
  if (h.matrix) {
    ojson rows = ojson::array();
    for (int r = 0; r < 4; ++r)
      rows.push_back({h.matrix->matrix()(r, 0), h.matrix->matrix()(r, 1), h.matrix->matrix()(r, 2), h.matrix->matrix()(r, 3)});
    j["matrix"] = std::move(rows);
  }
  return j;
}

class Reader {
 public:
  explicit Reader(std::string name) : name_(std::move(name)) {}

  Session session(const ojson& j) {
    object(j, "the session");
    keys(j, "", {"version", "mesh", "applied", "current"});
    const long long version = integer(required(j, "", "version"), "version");
    if (version != 1) fail("unsupported session \"version\" " + std::to_string(version) + " (this editor reads version 1)");
    Session s;
    const ojson& mesh = required(j, "", "mesh");
    object(mesh, "mesh");
    keys(mesh, "mesh", {"path", "relative", "vertices"});
    s.mesh_path = string(required(mesh, "mesh", "path"), "mesh.path");
    if (mesh.contains("relative")) s.mesh_relative = string(mesh["relative"], "mesh.relative");
    const long long n = integer(required(mesh, "mesh", "vertices"), "mesh.vertices");
    if (n < 1 || n > INT_MAX) fail(q("mesh.vertices") + " must be a positive vertex count, got " + std::to_string(n));
    s.n_vertices = static_cast<int>(n);
    if (j.contains("applied")) {
      const ojson& list = array(j["applied"], "applied");
      for (std::size_t i = 0; i < list.size(); ++i) {
        object(list[i], at("applied", i));
        s.applied.push_back(list[i]);
      }
    }
    current(required(j, "", "current"), s);
    return s;
  }

 private:
  std::string name_;

  [[noreturn]] void fail(const std::string& message) const { throw InvalidInput(name_ + ": " + message); }

  const ojson& required(const ojson& obj, const std::string& path, const char* key) const {
    if (!obj.contains(key)) fail("missing required key " + q(at(path, key)));
    return obj[key];
  }
  void keys(const ojson& obj, const std::string& path, std::initializer_list<const char*> allowed) const {
    for (const auto& [key, value] : obj.items()) {
      if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) continue;
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + "\"" + a + "\"";
      fail("unknown key " + q(at(path, key)) + " (allowed here: " + list + ")");
    }
  }
  void object(const ojson& j, const std::string& path) const {
    if (!j.is_object()) fail(q(path) + " must be an object, got " + type_of(j));
  }
  const ojson& array(const ojson& j, const std::string& path) const {
    if (!j.is_array()) fail(q(path) + " must be an array, got " + type_of(j));
    return j;
  }
  long long integer(const ojson& j, const std::string& path) const {
    if (j.is_number_unsigned()) return static_cast<long long>(std::min<unsigned long long>(j.get<unsigned long long>(), LLONG_MAX));
    if (!j.is_number_integer()) fail(q(path) + " must be an integer, got " + type_of(j));
    return j.get<long long>();
  }
  double number(const ojson& j, const std::string& path) const {
    if (!j.is_number()) fail(q(path) + " must be a number, got " + type_of(j));
    return j.get<double>();
  }
  bool boolean(const ojson& j, const std::string& path) const {
    if (!j.is_boolean()) fail(q(path) + " must be true or false, got " + type_of(j));
    return j.get<bool>();
  }
  std::string string(const ojson& j, const std::string& path) const {
    if (!j.is_string()) fail(q(path) + " must be a string, got " + type_of(j));
    return j.get<std::string>();
  }
  Vec3 vec3(const ojson& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(q(path) + " must be an array of 3 numbers [x, y, z]");
    return {number(j[0], at(path, 0)), number(j[1], at(path, 1)), number(j[2], at(path, 2))};
  }
  Vertex vertex(const ojson& j, const std::string& path, int n) const {
    const long long v = integer(j, path);
    if (v < 0 || v >= n)
      fail(q(path) + " is vertex " + std::to_string(v) + ", outside the mesh, which has vertices 0.." + std::to_string(n - 1));
    return Vertex(static_cast<int>(v));
  }

  void current(const ojson& j, Session& s) const {
    const std::string p = "current";
    object(j, p);
    keys(j, p, {"parameters", "support", "handles", "active_handle"});
    const int n = s.n_vertices;
    EditState state(n);
    if (j.contains("parameters")) state.set_parameters(parameters(j["parameters"], at(p, "parameters")));
    if (j.contains("support")) {
      const ojson& list = array(j["support"], at(p, "support"));
      for (std::size_t i = 0; i < list.size(); ++i) state.set_vertex(vertex(list[i], at(at(p, "support"), i), n), true, -1);
    }
    if (j.contains("handles")) {
      const ojson& list = array(j["handles"], at(p, "handles"));
      for (std::size_t i = 0; i < list.size(); ++i) handle(list[i], at(at(p, "handles"), i), state);
    }
    s.active_handle = -1;
    if (j.contains("active_handle")) {
      const std::string ap = at(p, "active_handle");
      const long long a = integer(j["active_handle"], ap);
      if (a != -1 && (a < 0 || a > INT_MAX || !state.find_handle(static_cast<int>(a))))
        fail(q(ap) + " must be -1 or the id of a handle, got " + std::to_string(a));
      s.active_handle = static_cast<int>(a);
    }
    s.current = std::move(state);
  }

  EditParameters parameters(const ojson& j, const std::string& p) const {
    object(j, p);
    keys(j, p, {"order", "outer", "inner", "anisotropic", "multiresolution"});
    EditParameters e;
    if (j.contains("order")) {
      const long long k = integer(j["order"], at(p, "order"));
      if (k < 1 || k > 3) fail(q(at(p, "order")) + " must be 1, 2 or 3, got " + std::to_string(k));
      e.order = static_cast<int>(k);
    }
    e.outer = e.inner = e.order - 1.0;
    for (const char* side : {"outer", "inner"}) {
      if (!j.contains(side)) continue;
      const double c = number(j[side], at(p, side));
      if (c < 0.0 || c > e.order - 1)
        fail(q(at(p, side)) + " must be in [0, " + std::to_string(e.order - 1) + "] for order " + std::to_string(e.order) +
             ", got " + num(c));
      (std::string(side) == "outer" ? e.outer : e.inner) = c;
    }
    if (j.contains("anisotropic")) e.anisotropic = boolean(j["anisotropic"], at(p, "anisotropic"));
    if (j.contains("multiresolution")) e.multiresolution = boolean(j["multiresolution"], at(p, "multiresolution"));
    return e;
  }

  void handle(const ojson& j, const std::string& p, EditState& state) const {
    object(j, p);
    keys(j, p, {"id", "movable", "vertices", "manipulator", "matrix"});
    const long long id = integer(required(j, p, "id"), at(p, "id"));
    if (id < 0 || id >= INT_MAX) fail(q(at(p, "id")) + " must be a non-negative integer, got " + std::to_string(id));
    if (state.find_handle(static_cast<int>(id))) fail(q(at(p, "id")) + " repeats the handle id " + std::to_string(id));
    HandleState h;
    h.id = static_cast<int>(id);
    if (j.contains("movable")) h.movable = boolean(j["movable"], at(p, "movable"));
    state.insert_handle(static_cast<int>(state.handles().size()), h);
    const ojson& list = array(required(j, p, "vertices"), at(p, "vertices"));
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string vp = at(at(p, "vertices"), i);
      const Vertex v = vertex(list[i], vp, state.n_vertices());
      const int other = state.handle_of(v);
      if (other >= 0 && other != h.id)
        fail(q(vp) + ": vertex " + std::to_string(v.idx()) + " is already in handle " + std::to_string(other) +
             " (handles must not overlap)");
      state.set_vertex(v, state.support_flag(v), h.id);
    }
    Manipulator m;
    if (j.contains("manipulator")) {
      const std::string mp = at(p, "manipulator");
      const ojson& mj = j["manipulator"];
      object(mj, mp);
      keys(mj, mp, {"translation", "rotation", "scale", "pivot"});
      if (mj.contains("translation")) m.translation = vec3(mj["translation"], at(mp, "translation"));
      if (mj.contains("scale")) m.scale = vec3(mj["scale"], at(mp, "scale"));
      if (mj.contains("pivot")) m.pivot = vec3(mj["pivot"], at(mp, "pivot"));
      if (mj.contains("rotation")) {
        const std::string rp = at(mp, "rotation");
        const ojson& r = mj["rotation"];
        if (!r.is_array() || r.size() != 4) fail(q(rp) + " must be a quaternion [w, x, y, z]");
        m.rotation = Eigen::Quaterniond(number(r[0], at(rp, 0)), number(r[1], at(rp, 1)), number(r[2], at(rp, 2)),
                                        number(r[3], at(rp, 3)));
      }
    }
    std::optional<Eigen::Affine3d> matrix;
    if (j.contains("matrix")) {
      const std::string xp = at(p, "matrix");
      const ojson& rows = j["matrix"];
      if (!rows.is_array() || rows.size() != 4) fail(q(xp) + " must be 4 rows of 4 numbers (row-major)");
      Eigen::Matrix4d mm;
      for (std::size_t r = 0; r < 4; ++r) {
        if (!rows[r].is_array() || rows[r].size() != 4) fail(q(at(xp, r)) + " must be a row of 4 numbers");
        for (std::size_t c = 0; c < 4; ++c) mm(static_cast<int>(r), static_cast<int>(c)) = number(rows[r][c], at(at(xp, r), c));
      }
      try {
        matrix = affine_from_matrix(mm);
      } catch (const InvalidInput& e) {
        fail(q(xp) + ": " + e.what());
      }
    }
    try {
      state.set_transform(h.id, m, matrix);
    } catch (const InvalidInput& e) {
      fail(q(at(p, "manipulator")) + ": " + e.what());
    }
  }
};

std::pair<std::size_t, std::size_t> line_column(std::string_view text, std::size_t pos) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < std::min(pos, text.size()); ++i) {
    col = text[i] == '\n' ? 1 : col + 1;
    line += text[i] == '\n' ? 1 : 0;
  }
  return {line, col};
}

}  // namespace

std::string session_text(const Session& s) {
  ojson current{{"parameters",
                 {{"order", s.current.parameters().order},
                  {"outer", s.current.parameters().outer},
                  {"inner", s.current.parameters().inner},
                  {"anisotropic", s.current.parameters().anisotropic},
                  {"multiresolution", s.current.parameters().multiresolution}}}};
  ojson support = ojson::array();
  for (int v = 0; v < s.current.n_vertices(); ++v)
    if (s.current.support_flag(Vertex(v))) support.push_back(v);
  current["support"] = std::move(support);
  ojson handles = ojson::array();
  for (const HandleState& h : s.current.handles()) handles.push_back(handle_json(h, s.current.handle_vertices(h.id)));
  current["handles"] = std::move(handles);
  current["active_handle"] = s.active_handle;
  ojson applied = ojson::array();
  for (const ojson& e : s.applied) applied.push_back(e);
  const ojson j{{"version", 1},
                {"mesh", {{"path", s.mesh_path}, {"relative", s.mesh_relative}, {"vertices", s.n_vertices}}},
                {"applied", std::move(applied)},
                {"current", std::move(current)}};
  return json_text(j, 4);
}

Session parse_session_text(std::string_view text, const std::string& name) {
  ojson j;
  std::vector<std::vector<std::string>> seen;  // keys of each open object
  std::string duplicate;
  const ojson::parser_callback_t check = [&](int, ojson::parse_event_t event, ojson& parsed) {
    if (event == ojson::parse_event_t::object_start) seen.emplace_back();
    if (event == ojson::parse_event_t::object_end && !seen.empty()) seen.pop_back();
    if (event == ojson::parse_event_t::key && !seen.empty() && duplicate.empty()) {
      const std::string key = parsed.get<std::string>();
      if (std::find(seen.back().begin(), seen.back().end(), key) != seen.back().end()) duplicate = key;
      seen.back().push_back(key);
    }
    return true;
  };
  try {
    j = ojson::parse(text, check);
  } catch (const ojson::parse_error& e) {
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string reason = e.what();
    const std::size_t colon = reason.find(": ", reason.find("parse error"));
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    throw IoError(name, line, "malformed JSON at column " + std::to_string(col) + ": " + reason);
  } catch (const ojson::exception& e) {
    throw IoError(name, 0, std::string("malformed JSON: ") + e.what());
  }
  if (!duplicate.empty()) throw InvalidInput(name + ": the key \"" + duplicate + "\" appears twice in one object");
  return Reader(name).session(j);
}

void write_session_file(const std::string& path, const Session& session) { write_file_atomic(path, session_text(session)); }

Session read_session_file(const std::string& path) { return parse_session_text(read_file(path), path); }

std::string session_mesh_file(const Session& session, const std::string& session_path) {
  std::error_code ec;
  if (!session.mesh_relative.empty()) {
    const fs::path p = fs::path(session_path).parent_path() / session.mesh_relative;
    if (fs::is_regular_file(p, ec)) return p.lexically_normal().string();
  }
  if (fs::is_regular_file(session.mesh_path, ec)) return session.mesh_path;
  throw IoError(session_path, 0,
                "the mesh file was found neither at \"" + session.mesh_relative + "\" (relative to the session) nor at \"" +
                    session.mesh_path + "\"");
}

LoadedSession load_session_file(const std::string& path) {
  Session s = read_session_file(path);
  LoadedSession out;
  out.mesh_file = session_mesh_file(s, path);
  ReadResult read = read_mesh(out.mesh_file);
  out.warnings = std::move(read.warnings);
  out.rest = Mesh::from_soup(read.soup);
  if (out.rest.n_vertices() != s.n_vertices)
    throw InvalidInput(path + ": the mesh " + out.mesh_file + " has " + std::to_string(out.rest.n_vertices()) +
                       " vertices, the session was saved with " + std::to_string(s.n_vertices) + ": the mesh file changed");
  const fs::path dir = fs::path(path).parent_path();
  for (std::size_t i = 0; i < s.applied.size(); ++i) {
    const std::string name = path + ": applied[" + std::to_string(i) + "]";
    Edit e = parse_edit(nlohmann::json(s.applied[i]), out.rest, name, dir);
    try {
      out.rest = deform(out.rest, e);
    } catch (const SolverError& err) {
      throw SolverError(name + ": " + err.what());
    } catch (const InvalidInput& err) {
      throw InvalidInput(name + ": " + err.what());
    }
    out.applied.push_back(std::move(e));
  }
  out.current = std::move(s.current);
  for (const HandleState& h : std::vector<HandleState>(out.current.handles()))
    if (!h.manipulator.pivot && out.current.handle_size(h.id) > 0)
      out.current.set_transform(h.id, recentred(h.manipulator, centroid(out.rest, out.current.handle_vertices(h.id))), h.matrix);
  out.active_handle = s.active_handle;
  return out;
}

}  // namespace freeform::editor
