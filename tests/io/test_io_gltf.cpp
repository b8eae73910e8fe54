// glTF 2.0: reading the assimp sample models (Debian's assimp-testmodels), rewriting them with
// new positions (only POSITION, NORMAL, TANGENT and their min/max change), errors, and new
// assets from write_gltf.
#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/gltf_util.h"
#include "freeform/io/mesh_io.h"
#include "test_support.h"

#include <Eigen/Geometry>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

namespace freeform::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kModels = "/usr/share/assimp/models/glTF2";

// Skips (fails when data is required, as in CI) without Debian's assimp-testmodels.
#define REQUIRE_MODELS()                                                                             \
  do {                                                                                               \
    if (!fs::is_directory(kModels)) {                                                                \
      if (data_required()) FAIL() << kModels << " missing: install assimp-testmodels (scripts/bootstrap.sh)"; \
      GTEST_SKIP() << kModels << " missing (Debian package assimp-testmodels)";                      \
    }                                                                                                \
  } while (0)

ReadResult read(const fs::path& path) {
  ReadResult r;
  read_gltf(read_file(path.string()), path.string(), r);
  return r;
}

std::string read_error(std::string_view data, const std::string& path) {
  try {
    ReadResult r;
    read_gltf(data, path, r);
  } catch (const IoError& e) {
    EXPECT_EQ(e.file(), path);
    return e.message();
  }
  ADD_FAILURE() << "expected an IoError for " << path;
  return {};
}

std::string file_error(const fs::path& path) { return read_error(read_file(path.string()), path.string()); }

// The JSON of a .gltf or .glb.
Json json_of(std::string_view data) {
  if (gltf_detail::is_glb(data)) data = gltf_detail::parse_glb(data, "x").json;
  return Json::parse(data);
}

// The JSON without what a rewrite may change: accessors' min/max, buffers' uri and byteLength.
Json without_changes(Json j) {
  for (Json& a : j["accessors"]) {
    a.erase("min");
    a.erase("max");
  }
  for (Json& b : j["buffers"]) {
    b.erase("uri");
    b.erase("byteLength");
  }
  return j;
}

// A rewritten file written to `dir` as `name` with its companions.
fs::path write_rewrite(const ReadResult& r, std::span<const Vec3> positions, const fs::path& dir, const std::string& name,
                       std::vector<std::pair<std::string, std::string>>* companions_out = nullptr) {
  std::vector<std::pair<std::string, std::string>> companions;
  const fs::path out = dir / name;
  const std::string data = r.source->rewrite(r, positions, companions, out.string());
  for (const auto& [file, bytes] : companions) write_file_atomic((dir / file).string(), bytes);
  write_file_atomic(out.string(), data);
  if (companions_out) *companions_out = companions;
  return out;
}

Vec3 row(const CornerAttribute& c, int corner) {
  const auto r = static_cast<std::size_t>(c.index[static_cast<std::size_t>(corner)]);
  return {c.values[r * 3], c.values[r * 3 + 1], c.values[r * 3 + 2]};
}

Eigen::Vector2d uv_of(const CornerAttribute& c, int corner) {
  const auto r = static_cast<std::size_t>(c.index[static_cast<std::size_t>(corner)]);
  return {c.values[r * 2], c.values[r * 2 + 1]};
}

std::vector<Vec3> transformed(const std::vector<Vec3>& p, const Eigen::Affine3d& t) {
  std::vector<Vec3> out;
  for (const Vec3& v : p) out.push_back(t * v);
  return out;
}

// ---------------------------------------------------------------------------------------------
// BoxTextured: .gltf + .bin, .glb, .gltf with a data: URI. A node matrix (x, y, z) -> (x, z, -y)
// above the mesh; 24 glTF vertices (4 per face) on the 8 corners of a cube.

class BoxTextured : public ::testing::TestWithParam<const char*> {
 protected:
  fs::path path() const { return kModels / GetParam(); }
};

TEST_P(BoxTextured, ReadsWeldedWorldSpaceCube) {
  REQUIRE_MODELS();
  const ReadResult r = read(path());
  EXPECT_EQ(r.format, MeshFormat::Gltf);
  EXPECT_EQ(r.soup.positions.size(), 8u);
  EXPECT_EQ(r.soup.faces.size(), 12u);
  EXPECT_EQ(r.attributes.polygons.size(), 12);
  ASSERT_EQ(r.attributes.triangle_polygon.size(), 12u);
  EXPECT_EQ(r.attributes.uv.width, 2);
  EXPECT_EQ(r.attributes.uv.rows(), 24);
  EXPECT_EQ(r.attributes.uv.index.size(), 36u);
  EXPECT_EQ(r.attributes.normal.rows(), 24);
  EXPECT_TRUE(r.warnings.empty());
  ASSERT_TRUE(r.source);
  EXPECT_EQ(r.source->binary(), path().extension() == ".glb");
  for (const Vec3& p : r.soup.positions)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(std::abs(p[k]), 0.5);
  // World-space normals are unit and perpendicular to their triangle.
  for (int c = 0; c < 36; ++c) {
    const Tri& t = r.soup.faces[static_cast<std::size_t>(c / 3)];
    const Vec3 face = (r.soup.positions[t[1]] - r.soup.positions[t[0]]).cross(r.soup.positions[t[2]] - r.soup.positions[t[0]]);
    EXPECT_NEAR(row(r.attributes.normal, c).dot(face.normalized()), 1.0, 1e-6) << "corner " << c;
  }
}

TEST_P(BoxTextured, SamePositionsGiveTheSameFile) {
  REQUIRE_MODELS();
  const ReadResult r = read(path());
  std::vector<std::pair<std::string, std::string>> companions;
  const std::string data = r.source->rewrite(r, r.soup.positions, companions, "/nonexistent/out" + path().extension().string());
  // In another folder, the files the input names beside itself come along, bytes and names kept.
  for (const auto& [name, bytes] : companions)
    EXPECT_EQ(bytes, read_file((path().parent_path() / name).string())) << name;
  // Only the first has files beside it (BoxTextured0.bin and its texture); the others embed both.
  EXPECT_EQ(companions.size(), std::string(GetParam()) == "BoxTextured-glTF/BoxTextured.gltf" ? 2u : 0u);
  const std::string in = read_file(path().string());
  EXPECT_EQ(json_of(data), json_of(in));
  if (r.source->binary()) {
    EXPECT_EQ(data.size(), in.size());  // BIN chunk kept byte for byte
  }
}

TEST_P(BoxTextured, MovedPositionsAreWrittenInTheNodeFrame) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const ReadResult r = read(path());
  const Eigen::Affine3d shift(Eigen::Translation3d(1, 2, 3));
  std::vector<std::pair<std::string, std::string>> companions;
  const fs::path out = write_rewrite(r, transformed(r.soup.positions, shift), dir.path(), "moved" + path().extension().string(), &companions);
  const std::string data = read_file(out.string());
  const Json j = json_of(data);
  // The node maps local (x, y, z) to world (x, z, -y): the world shift (1, 2, 3) is (1, -3, 2).
  const Json& position = j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
  EXPECT_EQ(position["min"], Json::parse("[0.5, -3.5, 1.5]"));
  EXPECT_EQ(position["max"], Json::parse("[1.5, -2.5, 2.5]"));
  EXPECT_EQ(without_changes(j), without_changes(json_of(read_file(path().string()))));
  const std::string uri = j["buffers"][0].value("uri", "");
  if (path().extension() == ".glb") {
    EXPECT_TRUE(companions.empty());
    EXPECT_EQ(uri, "");
  } else if (uri.rfind("data:", 0) == 0) {
    EXPECT_TRUE(companions.empty());
    EXPECT_EQ(uri.rfind("data:application/octet-stream;base64,", 0), 0u);
  } else {  // the patched buffer, and the texture the input has beside it
    ASSERT_EQ(companions.size(), 2u);
    EXPECT_EQ(companions[0].first, "moved.bin");
    EXPECT_EQ(uri, "moved.bin");
    EXPECT_EQ(companions[1].first, "CesiumLogoFlat.png");
  }
  const ReadResult back = read(out);
  ASSERT_EQ(back.soup.positions.size(), 8u);
  for (std::size_t v = 0; v < 8; ++v)
    EXPECT_NEAR((back.soup.positions[v] - shift * r.soup.positions[v]).norm(), 0, 1e-6);
}

TEST_P(BoxTextured, RotatedPositionsRotateTheNormals) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const ReadResult r = read(path());
  const Eigen::Affine3d rotation(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  const fs::path out = write_rewrite(r, transformed(r.soup.positions, rotation), dir.path(), "rotated" + path().extension().string());
  const ReadResult back = read(out);
  ASSERT_EQ(back.soup.faces.size(), 12u);
  for (int c = 0; c < 36; ++c) {
    const auto corner = static_cast<std::size_t>(c);
    const Vec3 expected = rotation * r.soup.positions[static_cast<std::size_t>(r.soup.faces[corner / 3][corner % 3])];
    EXPECT_NEAR((back.soup.positions[static_cast<std::size_t>(back.soup.faces[corner / 3][corner % 3])] - expected).norm(), 0, 1e-6);
    EXPECT_NEAR((row(back.attributes.normal, c) - rotation.linear() * row(r.attributes.normal, c)).norm(), 0, 1e-6) << c;
    EXPECT_EQ(uv_of(back.attributes.uv, c), uv_of(r.attributes.uv, c)) << c;
  }
}

INSTANTIATE_TEST_SUITE_P(Gltf, BoxTextured,
                         ::testing::Values("BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
                                           "BoxTextured-glTF-Embedded/BoxTextured.gltf"));

// BoxTextured.gltf and its BoxTextured0.bin copied into `dir`, read, with vertex 0 moved.
struct BoxBesideItsBin {
  std::string bin;  // the input buffer's bytes
  ReadResult r;
  std::vector<Vec3> moved;
  explicit BoxBesideItsBin(const fs::path& dir) {
    fs::copy_file(kModels / "BoxTextured-glTF/BoxTextured.gltf", dir / "BoxTextured.gltf");
    fs::copy_file(kModels / "BoxTextured-glTF/BoxTextured0.bin", dir / "BoxTextured0.bin");
    bin = read_file((dir / "BoxTextured0.bin").string());
    r = read(dir / "BoxTextured.gltf");
    moved = r.soup.positions;
    moved[0] *= 1.5;
  }
};

TEST(GltfRewrite, NeverOverwritesTheInputBuffer) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const auto [bin, r, moved] = BoxBesideItsBin(dir.path());
  std::vector<std::pair<std::string, std::string>> companions;
  // The output's own name would be BoxTextured0.bin: the input's buffer.
  write_rewrite(r, moved, dir.path(), "BoxTextured0.gltf", &companions);
  ASSERT_EQ(companions.size(), 1u);
  EXPECT_EQ(companions[0].first, "BoxTextured0-1.bin");
  EXPECT_EQ(read_file((dir / "BoxTextured0.bin").string()), bin);
  const ReadResult back = read(dir / "BoxTextured0.gltf");
  EXPECT_NEAR((back.soup.positions[0] - moved[0]).norm(), 0, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// The other container: .gltf written as .glb (buffer 0 becomes the BIN chunk) and .glb as .gltf
// (the BIN chunk becomes a companion .bin), through write_mesh, with everything else kept.

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Written into another folder, the .gltf's relative uris would name files that are not there
// (found converting assimp-testmodels' glTF samples: the output did not read back). The
// input's buffer and texture come along; an unrelated file of the same name there is kept.
TEST(GltfRewrite, AnotherFolderCarriesTheInputsFiles) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const fs::path in = kModels / "BoxTextured-glTF/BoxTextured.gltf";
  write_file_atomic((dir / "CesiumLogoFlat.png").string(), "not the texture");
  const ReadResult r = read(in);
  const std::vector<std::string> dropped = write_mesh((dir / "box.gltf").string(), r, r.soup.positions);
  EXPECT_TRUE(dropped.empty());
  EXPECT_EQ(files_in(dir.path()),
            (std::vector<std::string>{"BoxTextured0.bin", "CesiumLogoFlat-1.png", "CesiumLogoFlat.png", "box.gltf"}));
  EXPECT_EQ(read_file((dir / "CesiumLogoFlat.png").string()), "not the texture");
  const Json j = json_of(read_file((dir / "box.gltf").string()));
  EXPECT_EQ(j["images"][0]["uri"], "CesiumLogoFlat-1.png");
  EXPECT_EQ(read_file((dir / "CesiumLogoFlat-1.png").string()),
            read_file((in.parent_path() / "CesiumLogoFlat.png").string()));
  EXPECT_EQ(read_file((dir / "BoxTextured0.bin").string()),
            read_file((in.parent_path() / "BoxTextured0.bin").string()));
  const ReadResult back = read(dir / "box.gltf");
  EXPECT_EQ(back.soup.positions, r.soup.positions);
  // Back beside its files, nothing is carried: the same bytes as the input's JSON.
  std::vector<std::pair<std::string, std::string>> companions;
  EXPECT_EQ(back.source->rewrite(back, back.soup.positions, companions, (dir / "again.gltf").string()),
            read_file((dir / "box.gltf").string()));
  EXPECT_TRUE(companions.empty());
}

// The companions are committed only once the file itself is prepared: a file that cannot be
// written (here a link into a folder that does not exist) leaves nothing beside it.
TEST(GltfRewrite, AFailedWriteLeavesNoCompanionBehind) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const ReadResult r = read(kModels / "BoxTextured-glTF/BoxTextured.gltf");
  fs::create_symlink(dir / "missing/box.gltf", dir / "box.gltf");
  EXPECT_THROW(write_mesh((dir / "box.gltf").string(), r, r.soup.positions), IoError);
  EXPECT_EQ(files_in(dir.path()), (std::vector<std::string>{"box.gltf"}));
  // The same write to a path that can be written carries both files.
  (void)write_mesh((dir / "ok.gltf").string(), r, r.soup.positions);
  EXPECT_EQ(files_in(dir.path()),
            (std::vector<std::string>{"BoxTextured0.bin", "CesiumLogoFlat.png", "box.gltf", "ok.gltf"}));
}

// `back`, read from the converted file, has the positions `expected` and the uv and normals
// of `r` (moved by `t`).
void expect_converted(const ReadResult& r, const ReadResult& back, const Eigen::Affine3d& t) {
  ASSERT_EQ(back.soup.positions.size(), r.soup.positions.size());
  ASSERT_EQ(back.soup.faces, r.soup.faces);
  for (std::size_t v = 0; v < r.soup.positions.size(); ++v)
    EXPECT_NEAR((back.soup.positions[v] - t * r.soup.positions[v]).norm(), 0, 1e-6) << v;
  ASSERT_EQ(back.attributes.uv.index.size(), r.attributes.uv.index.size());
  for (int c = 0; c < static_cast<int>(r.attributes.uv.index.size()); ++c) {
    EXPECT_EQ(uv_of(back.attributes.uv, c), uv_of(r.attributes.uv, c)) << c;
    EXPECT_NEAR((row(back.attributes.normal, c) - t.linear() * row(r.attributes.normal, c)).norm(), 0, 1e-6) << c;
  }
}

class GltfConvert : public ::testing::TestWithParam<bool> {};  // moved positions or the read ones

TEST_P(GltfConvert, ExternalBinGltfToGlb) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const fs::path in = kModels / "BoxTextured-glTF/BoxTextured.gltf";
  const ReadResult r = read(in);
  const Eigen::Affine3d t(Eigen::Translation3d(GetParam() ? Vec3(1, 2, 3) : Vec3::Zero()));
  const std::vector<std::string> dropped = write_mesh((dir / "out.glb").string(), r, transformed(r.soup.positions, t));
  EXPECT_TRUE(dropped.empty());
  // No .bin: buffer 0 is the BIN chunk. The texture the input has beside it comes along.
  EXPECT_EQ(files_in(dir.path()), (std::vector<std::string>{"CesiumLogoFlat.png", "out.glb"}));
  EXPECT_EQ(read_file((dir / "CesiumLogoFlat.png").string()),
            read_file((in.parent_path() / "CesiumLogoFlat.png").string()));
  const std::string data = read_file((dir / "out.glb").string());
  ASSERT_TRUE(gltf_detail::is_glb(data));
  const gltf_detail::Glb glb = gltf_detail::parse_glb(data, "out.glb");
  ASSERT_TRUE(glb.bin);
  const Json j = json_of(data), original = json_of(read_file(in.string()));
  EXPECT_FALSE(j["buffers"][0].contains("uri"));
  EXPECT_EQ(j["buffers"][0]["byteLength"], original["buffers"][0]["byteLength"]);
  EXPECT_EQ(glb.bin->size(), (j["buffers"][0]["byteLength"].get<std::size_t>() + 3) / 4 * 4);
  EXPECT_EQ(without_changes(j), without_changes(original));
  EXPECT_EQ(j["materials"], original["materials"]);
  EXPECT_EQ(j["images"], original["images"]);
  if (!GetParam()) {  // the input's bytes, whole
    const std::string bin = read_file((in.parent_path() / "BoxTextured0.bin").string());
    EXPECT_EQ(glb.bin->substr(0, bin.size()), bin);
  }
  ReadResult back;
  read_gltf(data, (dir / "out.glb").string(), back);
  EXPECT_TRUE(back.source->binary());
  expect_converted(r, back, t);
}

TEST_P(GltfConvert, EmbeddedGltfToGlb) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const fs::path in = kModels / "BoxTextured-glTF-Embedded/BoxTextured.gltf";
  const ReadResult r = read(in);
  const Eigen::Affine3d t(Eigen::AngleAxisd(GetParam() ? 0.5 : 0.0, Vec3::UnitY()));
  write_mesh((dir / "embedded.glb").string(), r, transformed(r.soup.positions, t));
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"embedded.glb"});
  const std::string data = read_file((dir / "embedded.glb").string());
  const Json j = json_of(data), original = json_of(read_file(in.string()));
  ASSERT_TRUE(gltf_detail::parse_glb(data, "embedded.glb").bin);
  EXPECT_FALSE(j["buffers"][0].contains("uri"));
  EXPECT_EQ(without_changes(j), without_changes(original));
  EXPECT_EQ(j["images"], original["images"]);  // an embedded image stays a data: URI
  ReadResult back;
  read_gltf(data, "embedded.glb", back);
  expect_converted(r, back, t);
}

TEST_P(GltfConvert, GlbToGltfWithACompanionBin) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const fs::path in = kModels / "BoxTextured-glTF-Binary/BoxTextured.glb";
  const ReadResult r = read(in);
  const Eigen::Affine3d t(Eigen::Translation3d(GetParam() ? Vec3(-1, 0, 0.5) : Vec3::Zero()));
  const fs::path out = dir / "converted.gltf";
  write_mesh(out.string(), r, transformed(r.soup.positions, t));
  EXPECT_EQ(files_in(dir.path()), (std::vector<std::string>{"converted.bin", "converted.gltf"}));
  const std::string text = read_file(out.string());
  ASSERT_FALSE(gltf_detail::is_glb(text));
  const Json j = Json::parse(text), original = json_of(read_file(in.string()));
  EXPECT_EQ(j["buffers"][0]["uri"], "converted.bin");
  EXPECT_EQ(j["buffers"][0]["byteLength"], original["buffers"][0]["byteLength"]);
  const std::string bin = read_file((dir / "converted.bin").string());
  EXPECT_EQ(bin.size(), j["buffers"][0]["byteLength"].get<std::size_t>());  // no chunk padding
  if (!GetParam()) {
    EXPECT_EQ(bin, gltf_detail::parse_glb(read_file(in.string()), "in.glb").bin->substr(0, bin.size()));
  }
  EXPECT_EQ(without_changes(j), without_changes(original));
  EXPECT_EQ(j["materials"], original["materials"]);
  EXPECT_EQ(j["images"], original["images"]);  // images in a bufferView of the .bin
  const ReadResult back = read(out);
  EXPECT_FALSE(back.source->binary());
  expect_converted(r, back, t);
  // And back to a .glb: the companion becomes the BIN chunk again.
  write_mesh((dir / "again.glb").string(), back, back.soup.positions);
  const std::string again = read_file((dir / "again.glb").string());
  EXPECT_EQ(without_changes(json_of(again)), without_changes(original));
  EXPECT_FALSE(json_of(again)["buffers"][0].contains("uri"));
  ReadResult last;
  read_gltf(again, "again.glb", last);
  expect_converted(r, last, t);
}

std::string moved_name(const ::testing::TestParamInfo<bool>& p) { return p.param ? "Moved" : "Unmoved"; }
INSTANTIATE_TEST_SUITE_P(Gltf, GltfConvert, ::testing::Bool(), moved_name);

// Written as a .gltf of another name beside its input: the input's .bin (the name the output's
// own companion would have) is never overwritten, moved or not.
TEST(GltfConvert, NeverOverwritesTheInputBinBesideIt) {
  REQUIRE_MODELS();
  ScratchDir dir;
  const auto [bin, r, moved] = BoxBesideItsBin(dir.path());
  for (const bool move : {false, true}) {
    const std::span<const Vec3> positions = move ? std::span<const Vec3>(moved) : std::span<const Vec3>(r.soup.positions);
    write_mesh((dir / "BoxTextured0.gltf").string(), r, positions);
    EXPECT_EQ(read_file((dir / "BoxTextured0.bin").string()), bin) << move;
    const Json j = json_of(read_file((dir / "BoxTextured0.gltf").string()));
    EXPECT_EQ(j["buffers"][0]["uri"], move ? "BoxTextured0-1.bin" : "BoxTextured0.bin");
    const ReadResult back = read(dir / "BoxTextured0.gltf");
    EXPECT_NEAR((back.soup.positions[0] - positions[0]).norm(), 0, 1e-6);
  }
  // As a .glb beside it: the .bin is read, never written.
  write_mesh((dir / "BoxTextured0.glb").string(), r, moved);
  EXPECT_EQ(read_file((dir / "BoxTextured0.bin").string()), bin);
  EXPECT_NEAR((read(dir / "BoxTextured0.glb").soup.positions[0] - moved[0]).norm(), 0, 1e-6);
}

TEST(GltfRewrite, OnlyTheMovedVerticesChange) {
  REQUIRE_MODELS();
  const fs::path path = kModels / "BoxTextured-glTF-Binary/BoxTextured.glb";
  const ReadResult r = read(path);
  std::vector<Vec3> moved = r.soup.positions;
  moved[3] += Vec3(0.25, 0, 0);
  std::vector<std::pair<std::string, std::string>> companions;
  const std::string data = r.source->rewrite(r, moved, companions, "out.glb");
  ReadResult back;
  read_gltf(data, "out.glb", back);
  for (std::size_t v = 0; v < moved.size(); ++v) EXPECT_NEAR((back.soup.positions[v] - moved[v]).norm(), 0, 1e-7) << v;
  // The three faces around vertex 3 have new normals; the three others keep theirs.
  int changed = 0;
  for (int c = 0; c < 36; ++c) changed += (row(back.attributes.normal, c) - row(r.attributes.normal, c)).norm() > 1e-6 ? 1 : 0;
  EXPECT_GT(changed, 0);
  EXPECT_LT(changed, 36);
}

// ---------------------------------------------------------------------------------------------
// Animations, skins, morph targets, tangents, many nodes.

struct Sample {
  const char* file;
  const char* kept;  // a top-level key the rewrite must keep unchanged
};

class GltfSamples : public ::testing::TestWithParam<Sample> {};

TEST_P(GltfSamples, RewriteKeepsEverythingElse) {
  REQUIRE_MODELS();
  const fs::path path = kModels / GetParam().file;
  if (!fs::exists(path)) GTEST_SKIP() << path << " missing";
  ScratchDir dir;
  const ReadResult r = read(path);
  ASSERT_GT(r.soup.faces.size(), 0u);
  const Eigen::Affine3d t = Eigen::Translation3d(0.1, 0.2, 0.3) * Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()) * Eigen::Scaling(1.1);
  const fs::path out = write_rewrite(r, transformed(r.soup.positions, t), dir.path(), "out" + path.extension().string());
  const Json in = json_of(read_file(path.string())), written = json_of(read_file(out.string()));
  ASSERT_TRUE(in.contains(GetParam().kept));
  EXPECT_EQ(written[GetParam().kept], in[GetParam().kept]);
  EXPECT_EQ(without_changes(written), without_changes(in));
  const ReadResult back = read(out);
  ASSERT_EQ(back.soup.positions.size(), r.soup.positions.size());
  EXPECT_EQ(back.soup.faces, r.soup.faces);
  double scale = 1;
  for (const Vec3& p : r.soup.positions) scale = std::max(scale, p.norm());
  for (std::size_t v = 0; v < r.soup.positions.size(); ++v)
    ASSERT_NEAR((back.soup.positions[v] - t * r.soup.positions[v]).norm(), 0, 1e-6 * scale) << v;
}

INSTANTIATE_TEST_SUITE_P(Gltf, GltfSamples,
                         ::testing::Values(Sample{"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", "animations"},
                                           Sample{"simple_skin/simple_skin.gltf", "skins"},
                                           Sample{"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", "nodes"}));

TEST(GltfRead, WeldsAcrossPrimitivesAndNodes) {
  REQUIRE_MODELS();
  const fs::path path = kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (!fs::exists(path)) GTEST_SKIP() << path << " missing";
  const ReadResult r = read(path);
  const Json j = json_of(read_file(path.string()));
  std::size_t elements = 0;  // POSITION elements of every mesh
  for (const Json& m : j["meshes"])
    for (const Json& p : m["primitives"]) elements += j["accessors"][p["attributes"]["POSITION"].get<int>()]["count"].get<std::size_t>();
  EXPECT_LT(r.soup.positions.size(), elements);
  // Vertices shared by triangles of different primitives: some triangles use vertices from
  // two blocks of glTF rows.
  EXPECT_EQ(r.attributes.normal.index.size(), r.soup.faces.size() * 3);
}

TEST(GltfRead, MorphCubeTangentsStayOrthogonal) {
  REQUIRE_MODELS();
  const fs::path path = kModels / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  ScratchDir dir;
  const ReadResult r = read(path);
  std::vector<Vec3> moved = r.soup.positions;
  for (Vec3& p : moved) p = Vec3(p.x() * 2, p.y(), p.z() + 0.5 * p.x());  // shear: normals turn
  const fs::path out = write_rewrite(r, moved, dir.path(), "sheared.gltf");
  const Json j = json_of(read_file(out.string()));
  const std::string bin = read_file((dir / j["buffers"][0]["uri"].get<std::string>()).string());
  const Json& attributes = j["meshes"][0]["primitives"][0]["attributes"];
  const auto floats = [&](int accessor, int i, int n) {
    const Json& a = j["accessors"][accessor];
    const Json& v = j["bufferViews"][a["bufferView"].get<int>()];
    const std::size_t stride = v.value("byteStride", 4 * n);
    const std::size_t at = v.value("byteOffset", 0) + a.value("byteOffset", 0) + static_cast<std::size_t>(i) * stride;
    Eigen::Vector4d value = Eigen::Vector4d::Zero();
    for (int c = 0; c < n; ++c) {
      float f;
      std::memcpy(&f, bin.data() + at + 4 * static_cast<std::size_t>(c), 4);
      value[c] = f;
    }
    return value;
  };
  for (int i = 0; i < 24; ++i) {
    const Eigen::Vector4d n = floats(attributes["NORMAL"].get<int>(), i, 3), t = floats(attributes["TANGENT"].get<int>(), i, 4);
    EXPECT_NEAR(n.head<3>().norm(), 1, 1e-6);
    EXPECT_NEAR(t.head<3>().norm(), 1, 1e-6);
    EXPECT_NEAR(n.head<3>().dot(t.head<3>()), 0, 1e-6) << i;
    EXPECT_EQ(std::abs(t[3]), 1.0);
  }
}

TEST(GltfRead, PrimitiveModes) {
  REQUIRE_MODELS();
  const fs::path dir = kModels / "glTF-Asset-Generator/Mesh_PrimitiveMode";
  for (int m = 0; m <= 15; ++m) {
    const fs::path path = dir / ("Mesh_PrimitiveMode_" + std::string(m < 10 ? "0" : "") + std::to_string(m) + ".gltf");
    const bool lines_or_points = m <= 3 || (m >= 7 && m <= 10);
    if (lines_or_points) {
      EXPECT_THAT(file_error(path), HasSubstr("no faces (1 primitives of points or lines skipped)")) << path;
      continue;
    }
    const ReadResult r = read(path);
    EXPECT_EQ(r.soup.positions.size(), 4u) << path;
    ASSERT_EQ(r.soup.faces.size(), 2u) << path;
    // Both triangles of the quad face the same way.
    const auto normal = [&](const Tri& t) {
      return (r.soup.positions[t[1]] - r.soup.positions[t[0]]).cross(r.soup.positions[t[2]] - r.soup.positions[t[0]]);
    };
    EXPECT_GT(normal(r.soup.faces[0]).dot(normal(r.soup.faces[1])), 0) << path;
  }
}

// Every sample of the folder: an IoError, or a mesh whose rewrite with moved positions keeps
// everything but min/max and buffer uris.
TEST(GltfRead, EverySampleReadsOrFailsCleanly) {
  REQUIRE_MODELS();
  int read_ok = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kModels)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    ReadResult r;
    try {
      read_gltf(read_file(entry.path().string()), entry.path().string(), r);
    } catch (const IoError& e) {
      EXPECT_EQ(e.file(), entry.path().string());
      continue;
    }
    ++read_ok;
    std::vector<Vec3> moved = r.soup.positions;
    for (Vec3& p : moved) p = 1.25 * p + Vec3(0.5, 0, 0);
    std::vector<std::pair<std::string, std::string>> companions;
    const std::string data = r.source->rewrite(r, moved, companions, "/nonexistent/out" + ext);
    const Json original = without_changes(json_of(read_file(entry.path().string())));
    EXPECT_EQ(without_changes(json_of(data)), original) << entry.path();
    // The other container: the same JSON, and the same mesh read back.
    const std::string other = ext == ".glb" ? ".gltf" : ".glb";
    companions.clear();
    const std::string converted = r.source->rewrite(r, moved, companions, "/nonexistent/out" + other);
    EXPECT_EQ(gltf_detail::is_glb(converted), other == ".glb") << entry.path();
    EXPECT_EQ(without_changes(json_of(converted)), original) << entry.path();
    if (other == ".glb") {
      ReadResult back;
      read_gltf(converted, (entry.path().parent_path() / ("converted" + other)).string(), back);
      EXPECT_EQ(back.soup.faces.size(), r.soup.faces.size()) << entry.path();
    }
  }
  EXPECT_GE(read_ok, 20);
}

// ---------------------------------------------------------------------------------------------
// Errors: each names the element; never a crash.

TEST(GltfErrors, SampleFiles) {
  REQUIRE_MODELS();
  EXPECT_THAT(file_error(kModels / "MissingBin/BoxTextured.gltf"), HasSubstr("buffer 0: cannot read 'BoxTextured0.bin'"));
  EXPECT_THAT(file_error(kModels / "IndexOutOfRange/IndexOutOfRange.gltf"), HasSubstr("accessor 0: index 255 out of range (24 vertices)"));
  EXPECT_THAT(file_error(kModels / "IndexOutOfRange/AllIndicesOutOfRange.gltf"), HasSubstr("out of range"));
  EXPECT_THAT(file_error(kModels / "SchemaFailures/sceneWrongType.gltf"), HasSubstr("scene must be a non-negative integer, got a string"));
  EXPECT_THAT(file_error(kModels / "RecursiveNodes/RecursiveNodes.gltf"), HasSubstr("node 0 is reached twice"));
  EXPECT_THAT(file_error(kModels / "TestNoRootNode/NoScene.gltf"), HasSubstr("scene refers to scenes[0], which does not exist"));
  EXPECT_THAT(file_error(kModels / "TestNoRootNode/SceneWithoutNodes.gltf"), HasSubstr("no vertices"));
  EXPECT_THAT(file_error(kModels / "IncorrectVertexArrays/Cube.gltf"), HasSubstr("do not make whole triangles"));
  EXPECT_THAT(file_error(kModels / "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"), HasSubstr("is not finite"));
}

TEST(GltfErrors, WrongTypes) {
  REQUIRE_MODELS();
  const std::map<std::string, std::string> expected = {
      {"badArray.gltf", "meshes[0].primitives must be an array, got an object"},
      {"badExtension.gltf", "extensions.KHR_texture_transform must be an object, got a string"},
      {"badNumber.gltf", "materials[0].normalTexture.index is missing (required)"},
      {"badObject.gltf", "materials[0].pbrMetallicRoughness must be an object, got an array"},
      {"badString.gltf", "name must be a string, got the integer 42"},
      {"badUint.gltf", "baseColorTexture.index must be a non-negative integer, got the integer -1"},
  };
  for (const auto& [file, message] : expected) EXPECT_THAT(file_error(kModels / "wrongTypes" / file), HasSubstr(message)) << file;
}

TEST(GltfErrors, EmptyAndMalformed) {
  EXPECT_EQ(read_error("", "e.gltf"), "empty file");
  EXPECT_THAT(read_error("{", "e.gltf"), HasSubstr("malformed JSON"));
  EXPECT_THAT(read_error("[1]", "e.gltf"), HasSubstr("not a glTF file"));
  EXPECT_THAT(read_error("{}", "e.gltf"), HasSubstr("asset is missing (required)"));
  EXPECT_THAT(read_error(R"({"asset": {"version": "1.0"}})", "e.gltf"), HasSubstr("only glTF 2.x"));
  EXPECT_THAT(read_error(R"({"asset": {"version": "2.0"}, "asset": {"version": "2.0"}})", "e.gltf"), HasSubstr("twice"));
  EXPECT_THAT(read_error("glTF", "e.glb"), HasSubstr("file truncated"));
  const std::string deep = R"({"asset": {"version": "2.0"}, "extras": )" + std::string(100000, '[') + std::string(100000, ']') + "}";
  EXPECT_THAT(read_error(deep, "e.gltf"), HasSubstr("JSON nested 100001 levels deep"));
  EXPECT_THAT(read_error(R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 1e400}]})", "e.gltf"), HasSubstr("number overflow"));
}

TEST(GltfErrors, TruncatedAndCorruptedGlbNeverCrash) {
  REQUIRE_MODELS();
  const std::string glb = read_file((kModels / "BoxTextured-glTF-Binary/BoxTextured.glb").string());
  for (std::size_t n = 0; n < glb.size(); ++n) {
    try {
      ReadResult r;
      read_gltf(std::string_view(glb).substr(0, n), "t.glb", r);
      ADD_FAILURE() << "truncated to " << n << " bytes: no error";
    } catch (const IoError&) {
    }
  }
  // Every byte of the header and the JSON chunk changed in turn: an error or a mesh.
  const std::size_t json_end = 20 + gltf_detail::parse_glb(glb, "t.glb").json.size();
  int errors = 0;
  for (std::size_t i = 0; i < json_end; ++i) {
    for (const char c : {'\0', '9', '"', '}', '\xff'}) {
      std::string bad = glb;
      bad[i] = c;
      try {
        ReadResult r;
        read_gltf(bad, "t.glb", r);
        std::vector<std::pair<std::string, std::string>> companions;
        r.source->rewrite(r, r.soup.positions, companions, "out.glb");
      } catch (const Error&) {
        ++errors;
      }
    }
  }
  EXPECT_GT(errors, 0);
}

// Edits of a small asset made by write_gltf.
class GltfEdits : public ::testing::Test {
 protected:
  void SetUp() override {
    TriangleSoup soup;
    soup.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    soup.faces = {Tri{0, 1, 2}, Tri{0, 2, 3}};
    std::vector<std::string> dropped;
    json_ = Json::parse(write_gltf(soup, false, {}, dropped));
  }
  std::string error() { return read_error(json_.dump(), "edit.gltf"); }
  ReadResult read_json() {
    ReadResult r;
    read_gltf(json_.dump(), "edit.gltf", r);
    return r;
  }
  Json json_;
};

TEST_F(GltfEdits, Refusals) {
  Json original = json_;
  json_["accessors"][1]["sparse"] = Json::parse(R"({"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 1}})");
  EXPECT_THAT(error(), HasSubstr("accessor 1 (POSITION): sparse accessors are not supported"));
  json_ = original;
  json_["accessors"][1]["componentType"] = 5123;
  EXPECT_THAT(error(), HasSubstr("accessor 1 (POSITION): must hold float VEC3 values"));
  json_ = original;
  json_["extensionsRequired"] = Json::array({"KHR_draco_mesh_compression"});
  EXPECT_THAT(error(), HasSubstr("KHR_draco_mesh_compression"));
  json_ = original;
  json_["accessors"][1]["count"] = 1000000;
  EXPECT_THAT(error(), HasSubstr("accessor 1 (POSITION): 1000000 elements"));
  json_ = original;
  json_["bufferViews"][0]["byteOffset"] = 1ull << 62;
  EXPECT_THAT(error(), HasSubstr("bufferView 0 (byteOffset 4611686018427387904"));
  json_ = original;
  json_["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@@";
  EXPECT_THAT(error(), HasSubstr("buffer 0: data URI has a character outside base64"));
  json_ = original;
  json_["buffers"][0]["uri"] = "http://example.com/x.bin";
  EXPECT_THAT(error(), HasSubstr("is not a file beside the glTF file"));
  json_ = original;
  json_["meshes"][0]["primitives"][0]["indices"] = 7;
  EXPECT_THAT(error(), HasSubstr("meshes[0].primitives[0].indices refers to accessors[7], which does not exist (the file has 2)"));
}

TEST_F(GltfEdits, InstancedMeshDeformsTheFirstInstance) {
  json_["nodes"].push_back(Json::parse(R"({"mesh": 0, "translation": [5, 0, 0]})"));
  json_["scenes"][0]["nodes"].push_back(1);
  const ReadResult r = read_json();
  EXPECT_EQ(r.soup.positions.size(), 4u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "mesh 0 is instanced by nodes 0, 1: only node 0's instance is deformed (the others share its data and follow it)");
}

TEST_F(GltfEdits, PrimitivesSharingAnEdgeAreWelded) {
  // The square's two triangles as two meshes in two nodes, each with its own accessors (over
  // the same bytes): one deformable surface of 4 vertices.
  json_["accessors"][0]["count"] = 3;
  Json second_indices = json_["accessors"][0];
  second_indices["byteOffset"] = 12;
  json_["accessors"].push_back(second_indices);        // 2
  json_["accessors"].push_back(json_["accessors"][1]);  // 3: POSITION again
  Json mesh = json_["meshes"][0];
  mesh["primitives"][0]["indices"] = 2;
  mesh["primitives"][0]["attributes"]["POSITION"] = 3;
  json_["meshes"].push_back(mesh);
  json_["nodes"].push_back(Json::parse(R"({"mesh": 1})"));
  json_["scenes"][0]["nodes"].push_back(1);
  const ReadResult r = read_json();
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.soup.positions.size(), 4u);
  ASSERT_EQ(r.soup.faces.size(), 2u);
  EXPECT_EQ(r.soup.faces[0], (Tri{0, 1, 2}));
  EXPECT_EQ(r.soup.faces[1], (Tri{0, 2, 3}));
  std::vector<Vec3> moved = r.soup.positions;
  moved[2] = Vec3(2, 2, 0);
  std::vector<std::pair<std::string, std::string>> companions;
  ReadResult back;
  read_gltf(r.source->rewrite(r, moved, companions, "out.gltf"), "out.gltf", back);
  EXPECT_EQ(back.soup.positions, moved);
  EXPECT_EQ(r.source->kept_only_by_rewrite(), "the node hierarchy");
}

TEST_F(GltfEdits, NoSceneWalksTheRootNodes) {
  json_.erase("scene");
  json_.erase("scenes");
  json_["nodes"].push_back(Json::parse(R"({"children": [0], "translation": [0, 0, 2]})"));
  const ReadResult r = read_json();
  for (const Vec3& p : r.soup.positions) EXPECT_EQ(p.z(), 2);
}

TEST_F(GltfEdits, SkinnedMeshIgnoresItsNodeTransform) {
  json_["nodes"][0]["translation"] = Json::array({0, 0, 2});
  EXPECT_EQ(read_json().soup.positions[0].z(), 2);
  json_["skins"] = Json::parse(R"([{"joints": [0]}])");
  json_["nodes"][0]["skin"] = 0;
  EXPECT_EQ(read_json().soup.positions[0].z(), 0);
}

// Buffer 0 holding only an image, which no mesh reads: written as a .glb it is read then
// (decoded from its data: URI, or an IoError when its file is missing) and becomes the BIN chunk.
TEST_F(GltfEdits, UnreadBufferZeroBecomesTheBinChunk) {
  for (Json& view : json_["bufferViews"]) view["buffer"] = 1;
  json_["buffers"].insert(json_["buffers"].begin(), Json::parse(R"({"byteLength": 4, "uri": "data:application/octet-stream;base64,AAECAw=="})"));
  json_["bufferViews"].push_back(Json::parse(R"({"buffer": 0, "byteLength": 4})"));
  json_["images"] = Json::array({{{"bufferView", json_["bufferViews"].size() - 1}, {"mimeType", "image/png"}}});
  const Json original = json_;
  const ReadResult r = read_json();
  std::vector<Vec3> moved = r.soup.positions;
  moved[1] = Vec3(2, 0, 0);
  std::vector<std::pair<std::string, std::string>> companions;
  const std::string data = r.source->rewrite(r, moved, companions, "/nonexistent/out.glb");
  EXPECT_TRUE(companions.empty());
  const gltf_detail::Glb glb = gltf_detail::parse_glb(data, "out.glb");
  ASSERT_TRUE(glb.bin);
  EXPECT_EQ(*glb.bin, std::string("\x00\x01\x02\x03", 4));
  const Json j = json_of(data);
  EXPECT_FALSE(j["buffers"][0].contains("uri"));
  EXPECT_EQ(j["buffers"][1]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0), 0u);
  EXPECT_EQ(without_changes(j), without_changes(original));
  ReadResult back;
  read_gltf(data, "out.glb", back);
  EXPECT_EQ(back.soup.positions, moved);

  json_ = original;
  json_["buffers"][0]["uri"] = "missing.bin";
  const ReadResult missing = read_json();  // buffer 0 is never opened when reading
  EXPECT_NO_THROW(missing.source->rewrite(missing, moved, companions, "/nonexistent/out.gltf"));
  try {
    missing.source->rewrite(missing, moved, companions, "/nonexistent/out.glb");
    ADD_FAILURE() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.file(), "missing.bin");
    EXPECT_THAT(e.message(), HasSubstr("cannot embed buffer 0 in /nonexistent/out.glb"));
  }
}

// ---------------------------------------------------------------------------------------------
// write_gltf: new assets.

// A 3 x 2 grid of quads whose texture coordinates are cut along the middle column of vertices
// (a seam: those vertices have two rows), with a colour and a custom property per vertex.
ReadResult seam_grid() {
  ReadResult r;
  for (int y = 0; y <= 2; ++y)
    for (int x = 0; x <= 3; ++x) r.soup.positions.emplace_back(0.1 * x + 1.0 / 3.0, 0.2 * y, 0.05 * x * y);
  MeshAttributes& a = r.attributes;
  a.uv.width = 2;
  for (int y = 0; y <= 2; ++y)
    for (int x = 0; x <= 3; ++x) a.uv.values.insert(a.uv.values.end(), {x / 3.0, y / 2.0});
  for (int y = 0; y <= 2; ++y) a.uv.values.insert(a.uv.values.end(), {0.9, y / 2.0});  // seam rows 12..14 for x = 1
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const int v0 = y * 4 + x;
      const std::array<int, 4> quad{v0, v0 + 1, v0 + 5, v0 + 4};
      a.polygons.add(quad);
      for (const int v : quad) a.uv.index.push_back(x == 1 && v % 4 == 1 ? 12 + v / 4 : v);
      a.triangle_polygon.insert(a.triangle_polygon.end(), {a.polygons.size() - 1, a.polygons.size() - 1});
      r.soup.faces.push_back(Tri{quad[0], quad[1], quad[2]});
      r.soup.faces.push_back(Tri{quad[0], quad[2], quad[3]});
    }
  NamedAttribute color{"color", 3, {}}, quality{"quality", 1, {}};
  for (int v = 0; v < 12; ++v) {
    color.values.insert(color.values.end(), {v / 12.0, 0.5, 1.0});
    quality.values.push_back(v);
  }
  a.vertex = {color, quality};
  return r;
}

class GltfWrite : public ::testing::TestWithParam<bool> {};

TEST_P(GltfWrite, SeamGridRoundTrips) {
  const ReadResult grid = seam_grid();
  std::vector<std::string> dropped;
  const std::string data = write_gltf(grid.soup, GetParam(), grid.attributes, dropped);
  EXPECT_EQ(gltf_detail::is_glb(data), GetParam());
  EXPECT_THAT(dropped, ::testing::ElementsAre(HasSubstr("6 polygons with more than 3 corners"), HasSubstr("vertex property 'quality'")));
  ReadResult back;
  read_gltf(data, GetParam() ? "grid.glb" : "grid.gltf", back);
  const Json j = json_of(data);
  EXPECT_EQ(j["accessors"][1]["count"], 15);  // 12 vertices + 3 on the seam
  ASSERT_EQ(back.soup.faces.size(), grid.soup.faces.size());
  EXPECT_EQ(back.soup.positions.size(), 12u);
  ASSERT_FALSE(back.attributes.uv.empty());
  const NamedAttribute* color = back.attributes.vertex_attribute("color");
  ASSERT_TRUE(color);
  for (std::size_t c = 0; c < grid.soup.faces.size() * 3; ++c) {
    const int v = grid.soup.faces[c / 3][c % 3], w = back.soup.faces[c / 3][c % 3];
    EXPECT_EQ(back.soup.positions[static_cast<std::size_t>(w)], grid.soup.positions[static_cast<std::size_t>(v)].cast<float>().cast<double>());
    // The corner of the quad with this vertex: its uv row.
    const int p = grid.attributes.triangle_polygon[c / 3];
    int row = -1;
    for (int k = grid.attributes.polygons.offsets[static_cast<std::size_t>(p)]; k < grid.attributes.polygons.offsets[static_cast<std::size_t>(p) + 1]; ++k)
      if (grid.attributes.polygons.corners[static_cast<std::size_t>(k)] == v) row = grid.attributes.uv.index[static_cast<std::size_t>(k)];
    const Eigen::Vector2d expected(grid.attributes.uv.values[2 * static_cast<std::size_t>(row)], grid.attributes.uv.values[2 * static_cast<std::size_t>(row) + 1]);
    EXPECT_NEAR((uv_of(back.attributes.uv, static_cast<int>(c)) - expected).norm(), 0, 1e-7) << c;
    EXPECT_NEAR(color->values[static_cast<std::size_t>(w) * 3], v / 12.0, 1e-7);
  }
}

TEST_P(GltfWrite, NormalsAndEmptyMeshes) {
  ReadResult grid = seam_grid();
  polygons_from_triangles(grid.soup, grid.attributes);
  grid.attributes.uv = {};
  grid.attributes.vertex.clear();
  grid.attributes.normal.width = 3;
  for (int c = 0; c < 36; ++c) {
    grid.attributes.normal.values.insert(grid.attributes.normal.values.end(), {0.0, 0.0, c % 2 ? 2.0 : -2.0});
    grid.attributes.normal.index.push_back(c);
  }
  std::vector<std::string> dropped;
  ReadResult back;
  read_gltf(write_gltf(grid.soup, GetParam(), grid.attributes, dropped), "n.gltf", back);
  EXPECT_TRUE(dropped.empty());
  ASSERT_EQ(back.attributes.normal.rows(), 36);
  for (int c = 0; c < 36; ++c) EXPECT_EQ(row(back.attributes.normal, c), Vec3(0, 0, c % 2 ? 1 : -1));
  const std::string empty = write_gltf(TriangleSoup{}, GetParam(), {}, dropped);
  EXPECT_THAT(read_error(empty, "empty.gltf"), HasSubstr("no vertices"));
  TriangleSoup huge;
  huge.positions = {Vec3(1e300, 0, 0)};
  EXPECT_THROW(write_gltf(huge, GetParam(), {}, dropped), InvalidInput);
}

std::string encoding_name(const ::testing::TestParamInfo<bool>& p) { return p.param ? "Glb" : "Gltf"; }
INSTANTIATE_TEST_SUITE_P(Gltf, GltfWrite, ::testing::Bool(), encoding_name);

}  // namespace
}  // namespace freeform::test
