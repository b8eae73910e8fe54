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

class Reader : JsonReader {
 public:
  using JsonReader::JsonReader;

  Session session(const Json& j) {
    object(j, "the session");
    keys(j, "", {"version", "mesh", "applied", "current"});
    const long long version = integer(required(j, "", "version"), "version");
    if (version != 1) fail("unsupported session \"version\" " + std::to_string(version) + " (this editor reads version 1)");
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

  EditParameters parameters(const Json& j, const std::string& p, int n) const {
    object(j, p);
    keys(j, p, {"order", "outer", "inner", "anisotropic", "multiresolution", "nonlinear", "preserve_volume",
                "max_iterations", "tolerance", "allow_unanchored", "segments"});
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
    if (j.contains("nonlinear") && boolean(j["nonlinear"], at(p, "nonlinear"))) e.deformation = Deformation::Nonlinear;
    if (j.contains("preserve_volume"))
      e.nonlinear.preserve_volume = boolean(j["preserve_volume"], at(p, "preserve_volume"));
    if (j.contains("max_iterations")) {  // the ranges of edit files (edit_json.cpp)
      const long long m = integer(j["max_iterations"], at(p, "max_iterations"));
      if (m < 1 || m > 100000) fail(q(at(p, "max_iterations")) + " must be in [1, 100000], got " + std::to_string(m));
      e.nonlinear.max_iterations = static_cast<int>(m);
    }
    if (j.contains("tolerance")) {
      const double t = number(j["tolerance"], at(p, "tolerance"));
      if (!(t > 0.0 && t < 1.0)) fail(q(at(p, "tolerance")) + " must be in (0, 1), got " + num(t));
      e.nonlinear.tolerance = t;
    }
    if (j.contains("allow_unanchored")) e.allow_unanchored = boolean(j["allow_unanchored"], at(p, "allow_unanchored"));
    if (j.contains("segments")) {
      const std::string sp = at(p, "segments");
      const Json& list = array(j["segments"], sp);
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string ip = at(sp, i);
        object(list[i], ip);
        keys(list[i], ip, {"vertices", "value"});
        SmoothnessSegment seg;
        seg.value = number(required(list[i], ip, "value"), at(ip, "value"));
        if (seg.value < 0.0 || seg.value > e.order - 1)
          fail(q(at(ip, "value")) + " must be in [0, " + std::to_string(e.order - 1) + "], got " + num(seg.value));
        const Json& vs = array(required(list[i], ip, "vertices"), at(ip, "vertices"));
        for (std::size_t k = 0; k < vs.size(); ++k) seg.vertices.push_back(vertex(vs[k], at(at(ip, "vertices"), k), n));
        std::sort(seg.vertices.begin(), seg.vertices.end());
        seg.vertices.erase(std::unique(seg.vertices.begin(), seg.vertices.end()), seg.vertices.end());
        e.segments.push_back(std::move(seg));
      }
    }
    return e;
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
  Json current{{"parameters",
                 {{"order", s.current.parameters().order},
                  {"outer", s.current.parameters().outer},
                  {"inner", s.current.parameters().inner},
                  {"anisotropic", s.current.parameters().anisotropic},
                  {"multiresolution", s.current.parameters().multiresolution},
                  {"nonlinear", s.current.parameters().deformation == Deformation::Nonlinear},
                  {"preserve_volume", s.current.parameters().nonlinear.preserve_volume},
                  {"max_iterations", s.current.parameters().nonlinear.max_iterations},
                  {"tolerance", s.current.parameters().nonlinear.tolerance},
                  {"allow_unanchored", s.current.parameters().allow_unanchored}}}};
  if (!s.current.parameters().segments.empty()) {
    Json segments = Json::array();
    for (const SmoothnessSegment& seg : s.current.parameters().segments) {
      Json vs = Json::array();
      for (Vertex v : seg.vertices) vs.push_back(v.idx());
      segments.push_back(Json{{"vertices", std::move(vs)}, {"value", seg.value}});
    }
    current["parameters"]["segments"] = std::move(segments);
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
  const Json j{{"version", 1},
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
