// `freeform info MESH [--json]`: counts, bounding box, topology and every defect found.
#include "commands.h"

#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/validation.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <memory>

namespace freeform::cli {
namespace {

constexpr std::size_t kMaxListed = 100;  // indices listed per defect kind in the JSON

struct InfoOptions {
  std::string path;
  std::string format;
  bool json = false;
};

template <class T>
nlohmann::json first_items(const std::vector<T>& items) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < items.size() && i < kMaxListed; ++i) out.push_back(items[i]);
  return out;
}

double mean_edge_length(const Mesh& mesh) {
  if (mesh.n_edges() == 0) return 0.0;
  double sum = 0.0;
  for (Edge e : mesh.edges()) {
    const Halfedge h = mesh.halfedge(e, 0);
    sum += (mesh.position(mesh.to_vertex(h)) - mesh.position(mesh.from_vertex(h))).norm();
  }
  return sum / mesh.n_edges();
}

// What the file holds besides the triangles (kept when it is written back).
nlohmann::json describe_attributes(const ReadResult& read) {
  const MeshAttributes& a = read.attributes;
  nlohmann::json vertex = nlohmann::json::array(), face = nlohmann::json::array();
  for (const NamedAttribute& v : a.vertex) vertex.push_back(v.name);
  for (const NamedAttribute& f : a.face) face.push_back(f.name);
  return {{"format", format_name(read.format)},
          {"polygons", a.polygons.size()},
          {"texture_coordinates", a.uv.rows()},
          {"normals", a.normal.rows()},
          {"vertex", vertex},
          {"face", face}};
}

nlohmann::json describe(const InfoOptions& opt, const ReadResult& read) {
  const TriangleSoup& soup = read.soup;
  const ValidationReport r = validate(soup);
  const Mesh mesh = Mesh::from_soup(soup, BuildOptions{.repair = true});

  Vec3 lo = Vec3::Constant(0.0), hi = Vec3::Constant(0.0);
  if (!soup.positions.empty()) {
    lo = hi = soup.positions.front();
    for (const Vec3& p : soup.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  nlohmann::json components = nlohmann::json::array();
  for (const ComponentSummary& c : r.components)
    components.push_back({{"vertices", c.vertices},
                          {"faces", c.faces},
                          {"boundary_loops", c.boundary_loops},
                          {"euler_characteristic", c.euler_characteristic},
                          {"genus", c.genus}});
  nlohmann::json j = {
      {"file", opt.path},
      {"vertices", r.vertices},
      {"faces", r.faces},
      {"edges", mesh.n_edges()},
      {"bounding_box", {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}, {"diagonal", (hi - lo).norm()}}},
      {"mean_edge_length", mean_edge_length(mesh)},
      {"manifold", r.manifold()},
      {"boundary_loops", r.boundary_loops},
      {"components", r.components.size()},
      {"euler_characteristic", r.euler_characteristic},
      {"genus", r.genus},
      {"nonmanifold_edges", r.nonmanifold_edges.size()},
      {"nonmanifold_vertices", r.nonmanifold_vertices.size()},
      {"inconsistently_oriented_edges", r.inconsistent_edges.size()},
      {"degenerate_faces", r.zero_area_faces.size() + r.repeated_index_faces.size()},
      {"zero_area_faces", r.zero_area_faces.size()},
      {"repeated_index_faces", r.repeated_index_faces.size()},
      {"duplicate_vertices", r.duplicate_vertices.size()},
      {"unreferenced_vertices", r.unreferenced_vertices.size()},
      {"component_list", components},
      {"attributes", describe_attributes(read)},
      {"warnings", read.warnings},
      {"details",
       {{"note", "first " + std::to_string(kMaxListed) + " of each kind; edges as vertex pairs, 0-based"},
        {"nonmanifold_edges", first_items(r.nonmanifold_edges)},
        {"nonmanifold_vertices", first_items(r.nonmanifold_vertices)},
        {"inconsistently_oriented_edges", first_items(r.inconsistent_edges)},
        {"zero_area_faces", first_items(r.zero_area_faces)},
        {"repeated_index_faces", first_items(r.repeated_index_faces)},
        {"duplicate_vertices", first_items(r.duplicate_vertices)},
        {"unreferenced_vertices", first_items(r.unreferenced_vertices)}}},
  };
  return j;
}

void print_text(const nlohmann::json& j) {
  auto list = [&](const char* key) {
    const auto& items = j["details"][key];
    if (items.empty()) return std::string();
    std::string s = " (e.g.";
    for (std::size_t i = 0; i < std::min<std::size_t>(items.size(), 5); ++i) s += " " + items[i].dump();
    return s + ")";
  };
  const auto& bb = j["bounding_box"];
  fmt::print("file                  {}\n", j["file"].get<std::string>());
  fmt::print("vertices              {}\nfaces                 {}\nedges                 {}\n", j["vertices"].get<int>(),
             j["faces"].get<int>(), j["edges"].get<int>());
  fmt::print("bounding box          {} .. {} (diagonal {:.6g})\n", bb["min"].dump(), bb["max"].dump(),
             bb["diagonal"].get<double>());
  fmt::print("mean edge length      {:.6g}\n", j["mean_edge_length"].get<double>());
  fmt::print("components            {}\nboundary loops        {}\n", j["components"].get<std::size_t>(),
             j["boundary_loops"].get<int>());
  fmt::print("euler characteristic  {}\ngenus                 {}\n", j["euler_characteristic"].get<int>(),
             j["genus"].get<int>());
  fmt::print("manifold              {}\n", j["manifold"].get<bool>() ? "yes" : "no");
  const auto& a = j["attributes"];
  fmt::print("polygons              {}\ntexture coordinates   {}\nnormals               {}\n", a["polygons"].get<int>(),
             a["texture_coordinates"].get<int>(), a["normals"].get<int>());
  for (const char* kind : {"vertex", "face"})
    if (!a[kind].empty()) fmt::print("{:<22}{}\n", std::string(kind) + " attributes", a[kind].dump());
  for (const char* key : {"nonmanifold_edges", "nonmanifold_vertices", "inconsistently_oriented_edges", "zero_area_faces",
                          "repeated_index_faces", "duplicate_vertices", "unreferenced_vertices"})
    fmt::print("{:<22}{}{}\n", key, j[key].get<std::size_t>(), list(key));
  for (const auto& w : j["warnings"]) fmt::print("warning: {}\n", w.get<std::string>());
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto opt = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand("info", "Print counts, bounding box, topology and defects of a mesh");
  cmd->add_option("MESH", opt->path, "Mesh file (.obj, .off, .ply, .stl)")->required();
  cmd->add_option("--format", opt->format, "Input format, overriding the extension (obj|off|ply|stl|gltf)");
  cmd->add_flag("--json", opt->json, "Print JSON instead of text");
  cmd->footer(
      "Topology (components, loops, genus) is of the mesh after splitting non-manifold vertices.\n"
      "Exit codes: 0 ok, 1 unreadable or malformed input, 2 bad command line.");
  cmd->callback([opt] {
    ReadOptions ro;
    if (!opt->format.empty()) ro.format = parse_mesh_format(opt->format);
    const ReadResult read = read_mesh(opt->path, ro);
    const nlohmann::json j = describe(*opt, read);
    if (opt->json)
      fmt::print("{}\n", j.dump(2));
    else
      print_text(j);
  });
}

}  // namespace freeform::cli
