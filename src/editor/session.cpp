#include "editor/session.h"

#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>

namespace freeform::editor {
namespace {

namespace fs = std::filesystem;

using json_messages::num;
std::string at(const std::string& parent, const std::string& key) { return json_messages::key_path(parent, key); }
std::string at(const std::string& parent, std::size_t i) { return json_messages::index_path(parent, i); }
std::string q(const std::string& path) { return json_messages::quoted(path); }

Json vec_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json handle_json(const HandleState& h, const std::vector<Vertex>& vertices) {
  Json vs = Json::array();
  for (Vertex v : vertices) vs.push_back(v.idx());
  const Manipulator& m = h.manipulator;
  Json mj{{"translation", vec_json(m.translation)},
           {"rotation", Json::array({m.rotation.w(), m.rotation.x(), m.rotation.y(), m.rotation.z()})},
           {"scale", vec_json(m.scale)}};
  if (m.pivot) mj["pivot"] = vec_json(*m.pivot);
  Json j{{"id", h.id}, {"movable", h.movable}, {"vertices", std::move(vs)}, {"manipulator", std::move(mj)}};
  if (h.matrix) {
    Json rows = Json::array();
    for (int r = 0; r < 4; ++r)
      rows.push_back({h.matrix->matrix()(r, 0), h.matrix->matrix()(r, 1), h.matrix->matrix()(r, 2), h.matrix->matrix()(r, 3)});
    j["matrix"] = std::move(rows);
  }
  return j;
}

// Version 2 keeps the parameters with the keys of an edit file (edit_json.h); version 1 had
// its own (read by legacy_parameters).
constexpr int kVersion = 2;

class Reader : JsonReader {
 public:
  using JsonReader::JsonReader;

  Session session(const Json& j) {
    object(j, "the session");
    keys(j, "", {"version", "mesh", "applied", "current"});
    const long long version = integer(required(j, "", "version"), "version");
    if (version != 1 && version != kVersion)
      fail("unsupported session \"version\" " + std::to_string(version) + " (this editor reads versions 1 and " +
           std::to_string(kVersion) + ")");
    version_ = static_cast<int>(version);
    Session s;
    const Json& mesh = required(j, "", "mesh");
    object(mesh, "mesh");
    keys(mesh, "mesh", {"path", "relative", "vertices"});
    s.mesh_path = string(required(mesh, "mesh", "path"), "mesh.path");
    if (mesh.contains("relative")) s.mesh_relative = string(mesh["relative"], "mesh.relative");
    const long long n = integer(required(mesh, "mesh", "vertices"), "mesh.vertices");
    if (n < 1 || n > INT_MAX) fail(q("mesh.vertices") + " must be a positive vertex count, got " + std::to_string(n));
    s.n_vertices = static_cast<int>(n);
    if (j.contains("applied")) {
      const Json& list = array(j["applied"], "applied");
      for (std::size_t i = 0; i < list.size(); ++i) {
        object(list[i], at("applied", i));
        s.applied.push_back(list[i]);
      }
    }
    current(required(j, "", "current"), s);
    return s;
  }

 private:
  int version_ = kVersion;

  Vertex vertex(const Json& j, const std::string& path, int n) const {
    const long long v = integer(j, path);
    if (v < 0 || v >= n)
      fail(q(path) + " is vertex " + std::to_string(v) + ", outside the mesh, which has vertices 0.." + std::to_string(n - 1));
    return Vertex(static_cast<int>(v));
  }

  void current(const Json& j, Session& s) const {
    const std::string p = "current";
    object(j, p);
    keys(j, p, {"parameters", "support", "handles", "active_handle"});
    const int n = s.n_vertices;
    EditState state(n);
    if (j.contains("parameters")) state.set_parameters(parameters(j["parameters"], at(p, "parameters"), n));
    if (j.contains("support")) {
      const Json& list = array(j["support"], at(p, "support"));
      for (std::size_t i = 0; i < list.size(); ++i) state.set_vertex(vertex(list[i], at(at(p, "support"), i), n), true, -1);
    }
    if (j.contains("handles")) {
      const Json& list = array(j["handles"], at(p, "handles"));
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

  // The library reads the settings (the same checks and messages as edit files); the segments
  // keep the editor's painted vertices: {"region": {"vertices": [...]}, "value"}.
  EditParameters parameters(const Json& j, const std::string& p, int n) const {
    if (version_ == 1) return settings_parameters(legacy_parameters(j, p), p, n);
    return settings_parameters(j, p, n);
  }

  EditParameters settings_parameters(const Json& given, const std::string& p, int n) const {
    Json j = given;  // without "order": the editor's default order, which the smoothness is checked against
    if (j.is_object() && !j.contains("order")) j["order"] = EditParameters().settings.order;
    EditParameters e;
    static_cast<EditSettings&>(e) = parse_edit_settings(j, name() + ": " + p);
    if (!j.contains("smoothness") || !j["smoothness"].contains("segments")) return e;
    const std::string sp = at(at(p, "smoothness"), "segments");
    const Json& list = array(j["smoothness"]["segments"], sp);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string ip = at(sp, i);
      object(list[i], ip);
      keys(list[i], ip, {"region", "value"});
      SmoothnessSegment seg;
      seg.value = number(required(list[i], ip, "value"), at(ip, "value"));
      if (seg.value < 0.0 || seg.value > e.settings.order - 1)
        fail(q(at(ip, "value")) + " must be in [0, " + std::to_string(e.settings.order - 1) + "], got " + num(seg.value));
      const Json& region = required(list[i], ip, "region");
      object(region, at(ip, "region"));
      keys(region, at(ip, "region"), {"vertices"});
      const std::string vp = at(at(ip, "region"), "vertices");
      const Json& vs = array(required(region, at(ip, "region"), "vertices"), vp);
      for (std::size_t k = 0; k < vs.size(); ++k) seg.vertices.push_back(vertex(vs[k], at(vp, k), n));
      std::sort(seg.vertices.begin(), seg.vertices.end());
      seg.vertices.erase(std::unique(seg.vertices.begin(), seg.vertices.end()), seg.vertices.end());
      e.settings.smoothness.segments.push_back(std::move(seg));
    }
    return e;
  }

  // Version 1's parameters in version 2's keys (checked there).
  Json legacy_parameters(const Json& j, const std::string& p) const {
    object(j, p);
    keys(j, p, {"order", "outer", "inner", "anisotropic", "multiresolution", "nonlinear", "preserve_volume",
                "max_iterations", "tolerance", "allow_unanchored", "segments"});
    Json out = Json::object();
    for (const char* key : {"order", "anisotropic", "multiresolution", "allow_unanchored"})
      if (j.contains(key)) out[key] = j[key];
    for (const char* key : {"outer", "inner"})
      if (j.contains(key)) out["smoothness"][key] = j[key];
    if (j.contains("nonlinear"))
      out["deformation"] = deformation_name(boolean(j["nonlinear"], at(p, "nonlinear")) ? Deformation::Nonlinear
                                                                                        : Deformation::Linear);
    for (const char* key : {"preserve_volume", "max_iterations", "tolerance"})
      if (j.contains(key)) out["nonlinear"][key] = j[key];
    if (j.contains("segments")) {
      const Json& list = array(j["segments"], at(p, "segments"));
      Json segments = Json::array();
      for (std::size_t i = 0; i < list.size(); ++i) {
        object(list[i], at(at(p, "segments"), i));
        keys(list[i], at(at(p, "segments"), i), {"vertices", "value"});
        Json seg{{"region", Json::object()}};
        if (list[i].contains("vertices")) seg["region"]["vertices"] = list[i]["vertices"];
        if (list[i].contains("value")) seg["value"] = list[i]["value"];
        segments.push_back(std::move(seg));
      }
      out["smoothness"]["segments"] = std::move(segments);
    }
    return out;
  }

  void handle(const Json& j, const std::string& p, EditState& state) const {
    object(j, p);
    keys(j, p, {"id", "movable", "vertices", "manipulator", "matrix"});
    const long long id = integer(required(j, p, "id"), at(p, "id"));
    if (id < 0 || id >= INT_MAX) fail(q(at(p, "id")) + " must be a non-negative integer, got " + std::to_string(id));
    if (state.find_handle(static_cast<int>(id))) fail(q(at(p, "id")) + " repeats the handle id " + std::to_string(id));
    HandleState h;
    h.id = static_cast<int>(id);
    if (j.contains("movable")) h.movable = boolean(j["movable"], at(p, "movable"));
    state.insert_handle(static_cast<int>(state.handles().size()), h);
    const Json& list = array(required(j, p, "vertices"), at(p, "vertices"));
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
      const Json& mj = j["manipulator"];
      object(mj, mp);
      keys(mj, mp, {"translation", "rotation", "scale", "pivot"});
      if (mj.contains("translation")) m.translation = vec3(mj["translation"], at(mp, "translation"));
      if (mj.contains("scale")) m.scale = vec3(mj["scale"], at(mp, "scale"));
      if (mj.contains("pivot")) m.pivot = vec3(mj["pivot"], at(mp, "pivot"));
      if (mj.contains("rotation")) {
        const std::string rp = at(mp, "rotation");
        const Json& r = mj["rotation"];
        if (!r.is_array() || r.size() != 4) fail(q(rp) + " must be a quaternion [w, x, y, z]");
        m.rotation = Eigen::Quaterniond(number(r[0], at(rp, 0)), number(r[1], at(rp, 1)), number(r[2], at(rp, 2)),
                                        number(r[3], at(rp, 3)));
      }
    }
    std::optional<Eigen::Affine3d> matrix;
    if (j.contains("matrix")) {
      const std::string xp = at(p, "matrix");
      const Eigen::Matrix4d mm = matrix4(j["matrix"], xp);
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

}  // namespace

std::string session_text(const Session& s) {
  const EditParameters& params = s.current.parameters();
  Json current{{"parameters", edit_settings_to_json(params)}};
  if (!params.settings.smoothness.segments.empty()) {
    Json segments = Json::array();
    for (const SmoothnessSegment& seg : params.settings.smoothness.segments) {
      Json vs = Json::array();
      for (Vertex v : seg.vertices) vs.push_back(v.idx());
      segments.push_back(Json{{"region", {{"vertices", std::move(vs)}}}, {"value", seg.value}});
    }
    current["parameters"]["smoothness"]["segments"] = std::move(segments);
  }
  Json support = Json::array();
  for (int v = 0; v < s.current.n_vertices(); ++v)
    if (s.current.support_flag(Vertex(v))) support.push_back(v);
  current["support"] = std::move(support);
  Json handles = Json::array();
  for (const HandleState& h : s.current.handles()) handles.push_back(handle_json(h, s.current.handle_vertices(h.id)));
  current["handles"] = std::move(handles);
  current["active_handle"] = s.active_handle;
  Json applied = Json::array();
  for (const Json& e : s.applied) applied.push_back(e);
  const Json j{{"version", kVersion},
                {"mesh", {{"path", s.mesh_path}, {"relative", s.mesh_relative}, {"vertices", s.n_vertices}}},
                {"applied", std::move(applied)},
                {"current", std::move(current)}};
  return json_text(j, 4);
}

Session parse_session_text(std::string_view text, const std::string& name) {
  return Reader(name).session(parse_json_text(text, name));
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
  out.warnings = read.warnings;
  out.rest = Mesh::from_soup(read.soup);
  out.file = std::make_shared<const ReadResult>(std::move(read));
  if (out.rest.n_vertices() != s.n_vertices)
    throw InvalidInput(path + ": the mesh " + out.mesh_file + " has " + std::to_string(out.rest.n_vertices()) +
                       " vertices, the session was saved with " + std::to_string(s.n_vertices) + ": the mesh file changed");
  const fs::path dir = fs::path(path).parent_path();
  for (std::size_t i = 0; i < s.applied.size(); ++i) {
    const std::string name = path + ": applied[" + std::to_string(i) + "]";
    Edit e = parse_edit(s.applied[i], out.rest, name, dir);
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
