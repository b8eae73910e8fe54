// The gallery: the nonlinear model on seeded edits of real meshes and generated shapes
// (gallery_cases.h), against CGAL's Surface_mesh_deformation (ARAP, spokes and rims, and
// SR-ARAP) iterated toward convergence on the same support, handles and transforms, in the same
// run. Per case and method: folded edges, collapsed faces (smallest singular value of the face's
// deformation gradient < 0.5), min sigma, the support's mean compressive strain (rest-area
// weighted max(0, -ln sigma_min)) and its share of area halved, the largest dihedral increase, the volume ratio
// (closed meshes), iterations, converged, time. JSON on stdout, a summary table on stderr.
//   bench_gallery [--quick] [--no-peer] [--out DIR] [--peer-iterations N] [--seed S] [--linear-multires]
//                 [--config NAME]... [--case TEXT] [--mesh FILE]... [--assimp] [--drags | --scales | --turns | --bumps]
// --out writes each case's rest and deformed meshes (OFF) for scripts/gallery.sh's contact sheet, and the
// edit file of the Freeform run written (`freeform deform CASE-rest.off --edit CASE.edit.json` repeats it).
// --mesh: instead of the gallery's meshes, the same limb edits (3 limbs, support radius 0.2 of the
// diagonal) on any mesh files: meshes nobody tuned for, repaired as `freeform convert --repair` does.
// --assimp: the same on every OBJ, OFF, PLY, STL and glTF file of Debian's assimp-testmodels
// (/usr/share/assimp/models, or FREEFORM_ASSIMP_DIR) with at least 300 vertices.
// --drags: the limbs' handles moved without turning (a translate gizmo's edits; drag_cases): each
// dragged sideways by 40-100 % of the limb's length, the first also pushed toward the body by
// 20-40 %, instead of the bends, twists and pulls; no survey shapes. Likewise --scales: the
// handles scaled about their centres (scale_cases); --turns: turned in place about their centres
// (turn_cases); --bumps: discs of the surface pulled out or pushed in along their normal
// (bump_cases).
// --linear-multires: the linear model's multiresolution instead, both encodings (vertex frames,
// normal displacement) on the same cases with their rotations scaled to a third (edits linear
// BCM is made for) and on surface patches, judged by the same counts plus the detail heights
// against the BCM base; --out then writes the default encoding's k = 2 result per case.
#include "bench_meshes.h"
#include "build_paths.h"
#include "multires/detail_heights.h"
#include "nonlinear/gallery_cases.h"

#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/folds.h"
#include "freeform/mesh/generators.h"
#include "freeform/multires/multires_solver.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#ifdef FREEFORM_HAVE_CGAL
#include "nonlinear/cgal_arap.h"
#endif

namespace {

using namespace freeform;
using freeform::test::Shape;
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr double kCollapsedSigma = 0.5;

struct Config {
  std::string name;
  int order = 2;
  bool multiresolution = true;
  bool c0 = false;  // boundary smoothness 0 on both sides (default: k - 1)
  // NonlinearOptions: rotation_smoothing, max_iterations, preserve_volume
  int smoothing = -1, max_iterations = NonlinearOptions{}.max_iterations;
  bool volume = true;
  bool on_request = false;  // run only when named with --config
};

// Largest growth of an edge's dihedral angle (degrees) and the collapse counts.
nlohmann::json quality(const Shape& s, const VertexData<Vec3>& p, bool closed) {
  const Mesh& m = s.mesh;
  const VertexData<Vec3>& rest = m.positions();
  int collapsed = 0;
  double min_sv = std::numeric_limits<double>::infinity();
  // Over the support's faces (rest area weighted): the mean compressive strain max(0, -ln
  // sigma_min), how much the faces shrink however it is spread, and the share of area halved.
  std::vector<char> in_support(m.n_vertices(), 0);
  for (Vertex v : s.edit.support) in_support[static_cast<std::size_t>(v.idx())] = 1;
  double area = 0, compression = 0, halved = 0;
  for (Face f : m.faces()) {
    const Eigen::Vector2d sv = test::face_singular_values(m, rest, p, f);
    if (!(sv[1] >= kCollapsedSigma)) ++collapsed;
    min_sv = std::min(min_sv, std::isfinite(sv[1]) ? sv[1] : 0.0);
    const auto c = m.vertices(f);
    if (!std::any_of(c.begin(), c.end(), [&](Vertex v) { return in_support[static_cast<std::size_t>(v.idx())] != 0; }))
      continue;
    const double a = 0.5 * (rest[c[1]] - rest[c[0]]).cross(rest[c[2]] - rest[c[0]]).norm();
    area += a;
    compression += a * (sv[1] > 0.0 ? std::max(0.0, -std::log(sv[1])) : std::log(1e9));  // inverted: a large strain
    if (!(sv[0] * sv[1] >= 0.5)) halved += a;
  }
  auto dihedral = [&](const VertexData<Vec3>& x, Halfedge h) {
    const Vertex a = m.from_vertex(h), b = m.to_vertex(h);
    const Vertex c = m.to_vertex(m.next(h)), d = m.to_vertex(m.next(m.opposite(h)));
    const Vec3 n1 = (x[b] - x[a]).cross(x[c] - x[a]), n2 = (x[a] - x[b]).cross(x[d] - x[b]);
    return std::atan2(n1.cross(n2).norm(), n1.dot(n2));
  };
  double worst = 0;
  for (Halfedge h : m.halfedges())
    if (h.idx() < m.opposite(h).idx() && !m.is_boundary(h) && !m.is_boundary(m.opposite(h)))
      worst = std::max(worst, dihedral(p, h) - dihedral(rest, h));
  nlohmann::json j = {{"folded_edges", count_folded_edges(m, rest, p)},
                      {"collapsed_faces", collapsed},
                      {"min_sigma", min_sv},
                      {"compression", area > 0 ? compression / area : 0.0},
                      {"halved_area", area > 0 ? halved / area : 0.0},
                      {"max_dihedral_increase_deg", worst * 180.0 / std::numbers::pi}};
  if (closed) j["volume_ratio"] = test::volume(m, p) / test::volume(m, rest);
  return j;
}

// The case's edit with a configuration's settings and the nonlinear model.
Edit configured(const Edit& edit, const Config& c) {
  Edit e = edit;
  e.settings.order = c.order;
  e.multiresolution = c.multiresolution;
  if (c.c0) e.settings.smoothness.outer = e.settings.smoothness.inner = 0.0;
  e.deformation = Deformation::Nonlinear;
  e.nonlinear.rotation_smoothing = c.smoothing;
  e.nonlinear.max_iterations = c.max_iterations;
  e.nonlinear.preserve_volume = c.volume;
  return e;
}

nlohmann::json run_freeform(const Shape& shape, const Config& c, bool closed, VertexData<Vec3>& p) {
  Shape s = shape;
  s.edit = configured(shape.edit, c);
  nlohmann::json j = {{"method", "freeform " + c.name}};
  try {
    auto t = Clock::now();
    const EditSolver solver(s.mesh, s.edit);
    j["precompute_ms"] = ms_since(t);
    p = s.mesh.positions();
    t = Clock::now();
    solver.evaluate(solver.transforms(s.edit), p);
    j["solve_ms"] = ms_since(t);
    j["free"] = solver.regions().n_free();
    if (const NonlinearState* st = solver.nonlinear_state()) {
      j["iterations"] = st->iterations;
      j["converged"] = st->converged;
      j["step"] = st->step;
    }
    if (solver.stats().multires) {
      j["detail_by_model"] = solver.stats().multires->detail_by_model;
      j["detail_carried"] = !solver.detail_carried().empty();
      const MultiresProblems detail = solver.problems(p).detail;
      j["detail_flipped"] = detail.flipped;
      j["detail_overlaps"] = detail.overlaps;
    }
  } catch (const std::exception& e) {
    j["error"] = e.what();
    return j;
  }
  j.update(quality(s, p, closed));
  return j;
}

#ifdef FREEFORM_HAVE_CGAL
template <CGAL::Deformation_algorithm_tag Tag>
nlohmann::json run_cgal(const Shape& s, const char* name, int iterations, bool closed, VertexData<Vec3>& p) {
  const std::optional<test::PeerResult> r = test::cgal_deform<Tag>(s, iterations);
  if (!r) return {{"method", name}, {"error", "preprocess failed"}};
  p = r->positions;
  nlohmann::json j = {{"method", name},
                      {"precompute_ms", r->precompute_ms},
                      {"solve_ms", r->solve_ms},
                      {"max_iterations", iterations}};
  j.update(quality(s, p, closed));
  return j;
}
#endif

bool is_closed(const Mesh& m) {
  for (Halfedge h : m.halfedges())
    if (m.is_boundary(h)) return false;
  return true;
}

void write_result(const std::filesystem::path& dir, const std::string& stem, const Mesh& mesh,
                  const VertexData<Vec3>& p) {
  TriangleSoup soup = mesh.to_soup();
  soup.positions = p.raw();
  write_mesh((dir / (stem + ".off")).string(), soup);
}

// A command line this program cannot run: exit 2, as for any other usage error.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Options {
  bool quick = false, peer = true;
  std::string out;
  int peer_iterations = 2000;
  unsigned seed = 37;
  bool linear_multires = false;
  std::vector<std::string> configs;  // --config NAME (repeatable): only these Freeform runs
  std::string only;                  // --case TEXT: only the cases whose name contains it
  std::vector<std::string> meshes;   // --mesh FILE (repeatable): limb edits on these files only
  bool assimp = false;               // --assimp: limb edits on assimp-testmodels' files
  // Which edits: the limbs bent, twisted and pulled (limb_cases), or --drags, --scales, --turns, --bumps.
  test::CaseMaker family = test::limb_cases;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(a + " needs a value");
      return argv[++i];
    };
    if (a == "--quick")
      o.quick = true;
    else if (a == "--no-peer")
      o.peer = false;
    else if (a == "--out")
      o.out = value();
    else if (a == "--peer-iterations")
      o.peer_iterations = std::stoi(value());
    else if (a == "--seed")
      o.seed = static_cast<unsigned>(std::stoul(value()));
    else if (a == "--linear-multires")
      o.linear_multires = true;
    else if (a == "--config")
      o.configs.push_back(value());
    else if (a == "--case")
      o.only = value();
    else if (a == "--mesh")
      o.meshes.push_back(value());
    else if (a == "--assimp")
      o.assimp = true;
    else if (a == "--drags")
      o.family = test::drag_cases;
    else if (a == "--scales")
      o.family = test::scale_cases;
    else if (a == "--turns")
      o.family = test::turn_cases;
    else if (a == "--bumps")
      o.family = test::bump_cases;
    else
      throw UsageError("unknown option " + a);
  }
  return o;
}

// The mesh files of assimp-testmodels, sorted.
std::vector<std::string> assimp_files() {
  const char* env = std::getenv("FREEFORM_ASSIMP_DIR");
  const std::filesystem::path dir = env ? env : "/usr/share/assimp/models";
  if (!std::filesystem::is_directory(dir))
    throw std::runtime_error(dir.string() + " missing (apt-get install assimp-testmodels)");
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (e.is_regular_file() &&
        (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl" || ext == ".gltf" || ext == ".glb"))
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Limb edits on the files of --mesh or --assimp; a file that cannot be read, is smaller than
// kMinFileVertices or gives no limb is reported and skipped.
std::vector<Shape> file_gallery(const Options& o) {
  constexpr int kMinFileVertices = 300;
  std::vector<Shape> cases;
  std::mt19937 rng(o.seed);
  for (const std::string& file : o.assimp ? assimp_files() : o.meshes) {
    try {
      // As `freeform convert --repair` repairs them: real files split at non-manifold vertices.
      const Mesh mesh = Mesh::from_soup(read_mesh(file).soup, BuildOptions{.repair = true});
      if (mesh.n_vertices() < kMinFileVertices) continue;
      const std::filesystem::path path(file);
      const std::string label = path.parent_path().filename().string() + "-" + path.filename().string();
      std::vector<Shape> limbs = o.family(label, mesh, 3, 0.2, rng);
      if (limbs.empty()) std::fprintf(stderr, "gallery: %s: no limb found, skipped\n", file.c_str());
      for (Shape& s : limbs) cases.push_back(std::move(s));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "gallery: %s skipped: %s\n", file.c_str(), e.what());
    }
  }
  return cases;
}

std::vector<Shape> gallery(const Options& o) {
  if (!o.meshes.empty() || o.assimp) return file_gallery(o);
  std::vector<Shape> cases;
  const std::filesystem::path dir = freeform::bench::mesh_dir();
  if (o.family == test::limb_cases) {
    cases.push_back(test::flat_cylinder_bend());
    cases.push_back(test::bar_twist());
    cases.push_back(test::cylinder_bend());
    if (auto c = test::cactus_whole_bend(dir)) cases.push_back(std::move(*c));
  }
  // mesh, limbs, support radius (fraction of the diagonal), midpoint subdivisions
  struct Source {
    const char* name;
    int limbs;
    double radius;
    int subdivide;
  };
  std::vector<Source> sources = {{"armadillo", 3, 0.18, 0}, {"bunny00", 2, 0.2, 0},  {"elephant", 3, 0.2, 0},
                                 {"cactus", 2, 0.25, 1},    {"camel", 3, 0.2, 0},    {"cow", 3, 0.2, 0},
                                 {"dino", 3, 0.18, 0},      {"hand", 3, 0.2, 0},     {"triceratops", 3, 0.18, 0},
                                 {"man", 3, 0.18, 0},       {"elk", 3, 0.2, 0},      {"homer", 2, 0.2, 0},
                                 {"armadillo", 2, 0.3, 1},  {"bunny00", 1, 0.35, 1},  // large supports
                                 {"armadillo", 1, 0.3, 2}};                           // ~40k free
  if (o.quick) sources.resize(4);
  std::mt19937 rng(o.seed);
  for (const Source& src : sources) {
    const std::filesystem::path file = dir / (std::string(src.name) + ".off");
    if (!std::filesystem::exists(file)) {
      std::fprintf(stderr, "gallery: %s missing (scripts/fetch-data.sh), skipped\n", file.c_str());
      continue;
    }
    TriangleSoup soup = read_mesh(file.string()).soup;
    for (int i = 0; i < src.subdivide; ++i) soup = subdivide_midpoint(soup);
    const Mesh mesh = Mesh::from_soup(soup);
    const std::string label =
        src.subdivide > 0 ? std::string(src.name) + "-sub" + std::to_string(src.subdivide) : src.name;
    for (Shape& s : o.family(label, mesh, src.limbs, src.radius, rng)) cases.push_back(std::move(s));
  }
  return cases;
}

// A third of the transform's rotation angle and of its translation.
Eigen::Affine3d moderate(const Eigen::Affine3d& t) {
  const Eigen::AngleAxisd r(t.linear());
  Eigen::Affine3d out = Eigen::Affine3d::Identity();
  out.linear() = Eigen::AngleAxisd(r.angle() / 3.0, r.axis()).toRotationMatrix();
  out.translation() = t.translation() / 3.0;
  return out;
}

// The linear model's multiresolution with one encoding: the counts of quality(), and the height
// errors of the tall detail (|h| above half its largest) against the BCM base (multiresolution
// off), median and max.
nlohmann::json run_linear_multires(const Shape& shape, int order, MultiresOptions::Encoding encoding, bool closed,
                                   VertexData<Vec3>& p) {
  Shape s = shape;
  s.edit.settings.order = order;
  s.edit.multiresolution = false;
  const bool frames = encoding == MultiresOptions::Encoding::VertexFrame;
  nlohmann::json j = {{"method", std::string(frames ? "vertex frames" : "normal displacement") + " k" + std::to_string(order)}};
  try {
    const EditSolver plain(s.mesh, s.edit);
    const std::vector<Eigen::Affine3d> transforms = plain.transforms(s.edit);
    MultiresOptions options;
    options.encoding = encoding;
    const MultiresSolver solver(s.mesh, plain.regions(), s.edit.settings, options);
    p = s.mesh.positions();
    VertexData<Vec3> base0 = s.mesh.positions(), base1 = s.mesh.positions();
    solver.evaluate(transforms, p);
    plain.evaluate(std::vector<Eigen::Affine3d>(transforms.size(), Eigen::Affine3d::Identity()), base0);
    plain.evaluate(transforms, base1);
    const std::vector<double> h0 = test::detail_heights(s.mesh, plain.regions(), s.mesh.positions(), base0);
    const std::vector<double> h1 = test::detail_heights(s.mesh, plain.regions(), p, base1);
    const std::vector<double> err = test::tall_height_errors(h0, h1);
    j["height_error_median"] = err.empty() ? 0.0 : err[err.size() / 2];
    j["height_error_max"] = err.empty() ? 0.0 : err.back();
    j["flipped"] = solver.problems(p).flipped;
    j["smooth_operator"] = solver.stats().smooth_operator;
    j["operator_fallback"] = solver.stats().operator_fallback;
    j.update(quality(s, p, closed));
  } catch (const std::exception& e) {
    j["error"] = e.what();
  }
  return j;
}

// Patches of the surface away from the extremities: a geodesic ball of 12 % of the diagonal
// around a random vertex, its inner third lifted along the vertex normal by a quarter of the
// radius, or tilted by 25 degrees about a tangent through the handle's centre.
std::vector<Shape> patch_cases(const std::string& name, const Mesh& mesh, std::mt19937& rng) {
  Eigen::AlignedBox3d box;
  for (Vertex v : mesh.vertices()) box.extend(mesh.position(v));
  const double radius = 0.12 * box.diagonal().norm();
  std::uniform_int_distribution<int> pick(0, mesh.n_vertices() - 1);
  std::vector<Shape> out;
  for (int k = 0; k < 3; ++k) {
    const Vertex seed(pick(rng));
    const std::optional<test::Limb> l = test::limb(mesh, seed, radius);
    if (!l) continue;
    Vec3 n = Vec3::Zero();
    for (Halfedge h : mesh.outgoing(seed))
      if (mesh.face(h).is_valid()) {
        const auto v = mesh.vertices(mesh.face(h));
        n += (mesh.position(v[1]) - mesh.position(v[0])).cross(mesh.position(v[2]) - mesh.position(v[0]));
      }
    if (!(n.norm() > 0)) continue;
    n.normalize();
    const std::string stem = name + "-patch" + std::to_string(seed.idx());
    out.push_back(test::limb_case(stem + "-lift", mesh, {&*l},
                                  {Eigen::Affine3d(Eigen::Translation3d(0.25 * radius * n))}));
    out.push_back(test::limb_case(stem + "-tilt25", mesh, {&*l}, {test::rotation_about(l->tip, 25, n.unitOrthogonal())}));
  }
  return out;
}

int linear_multires_gallery(const Options& o) {
  nlohmann::json out = nlohmann::json::array();
  std::vector<Shape> cases = gallery(o);
  for (Shape& s : cases)
    for (EditHandle& h : s.edit.handles)
      if (h.matrix) h.matrix = moderate(*h.matrix);
  std::mt19937 rng(o.seed);
  for (const char* name : {"armadillo", "bunny00", "elephant", "camel", "cow", "dino", "hand", "triceratops", "man",
                           "elk", "homer", "fandisk", "rockerarm", "blobby", "pig"}) {
    const std::filesystem::path file = freeform::bench::mesh_dir() / (std::string(name) + ".off");
    if (!std::filesystem::exists(file)) continue;
    const Mesh mesh = Mesh::from_soup(read_mesh(file.string()).soup);
    for (Shape& s : patch_cases(name, mesh, rng)) cases.push_back(std::move(s));
  }
  for (Shape s : cases) {
    const bool closed = is_closed(s.mesh);
    nlohmann::json runs = nlohmann::json::array();
    for (int k : {2, 3}) {
      VertexData<Vec3> frames, displaced;
      runs.push_back(run_linear_multires(s, k, MultiresOptions::Encoding::VertexFrame, closed, frames));
      runs.push_back(run_linear_multires(s, k, MultiresOptions::Encoding::Normal, closed, displaced));
      // --out: the default's choice at k = 2 (vertex frames where the smooth shape exists).
      if (!o.out.empty() && k == 2 && !runs.back().contains("error"))
        write_result(o.out, s.name + "-linear-multires", s.mesh,
                     runs.back()["smooth_operator"].get<bool>() ? frames : displaced);
    }
    if (!o.out.empty()) write_result(o.out, s.name + "-rest", s.mesh, s.mesh.positions());
    std::fprintf(stderr, "%-34s", s.name.c_str());
    for (const nlohmann::json& r : runs)
      if (r.contains("error"))
        std::fprintf(stderr, " | error");
      else
        std::fprintf(stderr, " | %4d %5.1f%%", r["folded_edges"].get<int>(), 100 * r["height_error_max"].get<double>());
    std::fprintf(stderr, "\n");
    out.push_back({{"case", s.name}, {"runs", runs}});
  }
  std::cout << out.dump(1) << "\n";
  return 0;
}

// "k2", "k3", ... for the refusal of an unknown --config.
std::string config_names(const std::vector<Config>& configs) {
  std::string names;
  for (const Config& c : configs) names += (names.empty() ? "'" : ", '") + c.name + "'";
  return names;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  if (!o.out.empty()) std::filesystem::create_directories(o.out);
  if (o.linear_multires) return linear_multires_gallery(o);
  std::vector<Config> configs = {{"k2", 2, true, false},
                                 {"k3", 3, true, false},
                                 {"k2 multires off", 2, false, false},
                                 {"k3 multires off", 3, false, false},
                                 {"k2 C0", 2, true, true},
                                 // order 1 with the 1-ring fit and no volume term: ARAP's own alternation
                                 {"k1 arap", 1, false, false, 0, 1000, false, true}};
  for (const std::string& name : o.configs)
    if (std::none_of(configs.begin(), configs.end(), [&](const Config& c) { return c.name == name; }))
      throw UsageError("unknown configuration '" + name + "' (known: " + config_names(configs) + ")");
  std::erase_if(configs, [&](const Config& c) {
    return o.configs.empty() ? c.on_request
                             : std::find(o.configs.begin(), o.configs.end(), c.name) == o.configs.end();
  });
  nlohmann::json out = nlohmann::json::array();
  for (const Shape& s : gallery(o)) {
    if (s.name.find(o.only) == std::string::npos) continue;
    const bool closed = is_closed(s.mesh);
    nlohmann::json runs = nlohmann::json::array();
    VertexData<Vec3> p;
    for (const Config& c : configs) {
      runs.push_back(run_freeform(s, c, closed, p));
      if (!o.out.empty() && (c.name == "k3" || configs.size() == 1)) {
        if (!runs.back().contains("error")) write_result(o.out, s.name + "-freeform", s.mesh, p);
        write_edit_file((std::filesystem::path(o.out) / (s.name + ".edit.json")).string(), configured(s.edit, c));
      }
    }
#ifdef FREEFORM_HAVE_CGAL
    if (o.peer) {
      runs.push_back(run_cgal<CGAL::SPOKES_AND_RIMS>(s, "CGAL ARAP", o.peer_iterations, closed, p));
      if (!o.out.empty()) write_result(o.out, s.name + "-arap", s.mesh, p);
      runs.push_back(run_cgal<CGAL::SRE_ARAP>(s, "CGAL SR-ARAP", o.peer_iterations, closed, p));
    }
#endif
    if (!o.out.empty()) write_result(o.out, s.name + "-rest", s.mesh, s.mesh.positions());
    out.push_back({{"case", s.name},
                   {"vertices", s.mesh.n_vertices()},
                   {"support", s.edit.support.size()},
                   {"handles", s.edit.handles.size()},
                   {"closed", closed},
                   {"runs", runs}});
    std::fprintf(stderr, "%-34s", s.name.c_str());
    for (const nlohmann::json& r : runs)
      if (r.contains("error"))
        std::fprintf(stderr, " | error");
      else
        std::fprintf(stderr, " | %4d %4d", r["folded_edges"].get<int>(), r["collapsed_faces"].get<int>());
    std::fprintf(stderr, "\n");
  }
  if (out.empty() && !o.only.empty()) throw UsageError("no case's name contains '" + o.only + "' (--case)");
  if (out.empty()) throw std::runtime_error("no case to run: no limb edit on the meshes given");
  std::cout << out.dump(1) << "\n";
  return 0;
} catch (const UsageError& e) {
  std::fprintf(stderr, "bench_gallery: %s\n", e.what());
  return 2;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_gallery: %s\n", e.what());
  return 1;
}
