// Every settings key of an edit file (docs/edit-format.md) survives the editor: edit file ->
// editor document -> exported edit file, and edit file -> session -> edit file, compared key by
// key against the file. The editor and sessions hold the library's EditSettings and read and
// write them through edit_json, so a setting added there needs no change here.
#include "editor/document.h"
#include "editor/session.h"

#include "freeform/edit/edit_json.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace freeform::editor {
namespace {

namespace fs = std::filesystem;

// Every settings key away from its default (EditSettingsAreAllSet checks that).
constexpr const char* kEdit = R"({"order": 3,
  "support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.35}},
  "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.08}}, "transform": {"translate": [0, 0, 0.1]}}],
  "smoothness": {"outer": 0.5, "inner": 1.25,
                 "segments": [{"region": {"sphere": {"center": [0.92, 0.5, 0], "radius": 0.1}}, "value": 1.5}]},
  "anisotropic": true, "multiresolution": false, "deformation": "nonlinear",
  "nonlinear": {"max_iterations": 250, "tolerance": 3e-05, "preserve_volume": false},
  "allow_unanchored": true})";

class SettingsRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh_path_ = (dir_ / "plane.obj").string();
    write_mesh(mesh_path_, make_bumpy_plane(16, 16, 0.05, 2.0));
    mesh_ = Mesh::from_soup(read_mesh(mesh_path_).soup);
    edit_path_ = (dir_ / "edit.json").string();
    write_file_atomic(edit_path_, kEdit);
  }

  // Each settings key of `back` equals the file's; segments compared as the vertices they select.
  void expect_same_settings(const Json& back) const {
    const Json file = Json::parse(kEdit);
    for (const char* key : kEditSettingsKeys) {
      ASSERT_TRUE(file.contains(key)) << key;
      ASSERT_TRUE(back.contains(key)) << "dropped: " << key;
      if (std::string(key) == "smoothness") continue;
      EXPECT_EQ(back[key], file[key]) << key;
    }
    EXPECT_EQ(back["smoothness"]["outer"], file["smoothness"]["outer"]);
    EXPECT_EQ(back["smoothness"]["inner"], file["smoothness"]["inner"]);
    const Edit a = parse_edit(file, mesh_, "file", dir_.path());
    const Edit b = parse_edit(back, mesh_, "back", dir_.path());
    ASSERT_EQ(a.settings.smoothness.segments.size(), 1u);
    EXPECT_EQ(b.settings.smoothness.segments, a.settings.smoothness.segments);
    EXPECT_TRUE(static_cast<const EditSettings&>(b) == static_cast<const EditSettings&>(a));
  }

  Session session_of_the_edit() const {
    Session s;
    s.mesh_path = mesh_path_;
    s.n_vertices = mesh_.n_vertices();
    s.current = EditState::from_edit(parse_edit(Json::parse(kEdit), mesh_, "file", dir_.path()), mesh_, 0);
    return s;
  }

  test::ScratchDir dir_;
  std::string mesh_path_, edit_path_;
  Mesh mesh_;
};

TEST_F(SettingsRoundTrip, EditSettingsAreAllSet) {
  const EditSettings s = parse_edit(Json::parse(kEdit), mesh_, "file", dir_.path());
  const EditSettings d;
  EXPECT_NE(s.settings.order, d.settings.order);
  EXPECT_NE(s.settings.smoothness.outer, d.settings.smoothness.outer);
  EXPECT_NE(s.settings.smoothness.inner, d.settings.smoothness.inner);
  EXPECT_NE(s.settings.smoothness.segments, d.settings.smoothness.segments);
  EXPECT_NE(s.settings.anisotropic, d.settings.anisotropic);
  EXPECT_NE(s.multiresolution, d.multiresolution);
  EXPECT_NE(s.deformation, d.deformation);
  EXPECT_NE(s.nonlinear.max_iterations, d.nonlinear.max_iterations);
  EXPECT_NE(s.nonlinear.tolerance, d.nonlinear.tolerance);
  EXPECT_NE(s.nonlinear.preserve_volume, d.nonlinear.preserve_volume);
  EXPECT_NE(s.allow_unanchored, d.allow_unanchored);
}

TEST_F(SettingsRoundTrip, EditFileThroughTheEditorDocument) {
  Document doc;
  doc.open(mesh_path_);
  doc.import_edit(edit_path_);
  const std::string out = (dir_ / "export.json").string();
  doc.export_edit(out);
  expect_same_settings(Json::parse(read_file(out)));
}

TEST_F(SettingsRoundTrip, EditFileThroughASession) {
  const Session s = session_of_the_edit();
  const Session back = parse_session_text(session_text(s), "s.json");
  EXPECT_TRUE(back.current == s.current);
  expect_same_settings(edit_to_json(back.current.to_edit(mesh_)));
}

// Sessions written before the edit-file keys (version 1) still load, with the same values for
// the settings version 1 has (settings added since keep their defaults).
TEST_F(SettingsRoundTrip, Version1SessionParameters) {
  const Session s = session_of_the_edit();
  Json j = Json::parse(session_text(s));
  const EditParameters& p = s.current.parameters();
  Json v1{{"order", p.settings.order},
          {"outer", p.settings.smoothness.outer},
          {"inner", p.settings.smoothness.inner},
          {"anisotropic", p.settings.anisotropic},
          {"multiresolution", p.multiresolution},
          {"nonlinear", p.deformation == Deformation::Nonlinear},
          {"preserve_volume", p.nonlinear.preserve_volume},
          {"max_iterations", p.nonlinear.max_iterations},
          {"tolerance", p.nonlinear.tolerance},
          {"allow_unanchored", p.allow_unanchored}};
  Json segments = Json::array();
  for (const SmoothnessSegment& seg : p.settings.smoothness.segments) {
    Json vs = Json::array();
    for (Vertex v : seg.vertices) vs.push_back(v.idx());
    segments.push_back(Json{{"vertices", vs}, {"value", seg.value}});
  }
  v1["segments"] = segments;
  j["version"] = 1;
  j["current"]["parameters"] = v1;
  const Session back = parse_session_text(j.dump(), "v1.json");
  EditParameters expected;  // version 1's settings, and no other
  expected.settings = p.settings;
  expected.multiresolution = p.multiresolution;
  expected.deformation = p.deformation;
  expected.nonlinear.preserve_volume = p.nonlinear.preserve_volume;
  expected.nonlinear.max_iterations = p.nonlinear.max_iterations;
  expected.nonlinear.tolerance = p.nonlinear.tolerance;
  expected.allow_unanchored = p.allow_unanchored;
  EXPECT_TRUE(back.current.parameters() == expected);
  EditState rest_of_it = s.current;
  rest_of_it.set_parameters(expected);
  EXPECT_TRUE(back.current == rest_of_it);
  j["current"]["parameters"]["tolerance"] = 2.0;
  EXPECT_THROW(parse_session_text(j.dump(), "v1.json"), InvalidInput);
}

// A session without "order" has the editor's default order, and its smoothness is checked
// against that order (not the library's default).
TEST_F(SettingsRoundTrip, SessionWithoutOrderTakesTheEditorsDefault) {
  Json j = Json::parse(session_text(session_of_the_edit()));
  Json& params = j["current"]["parameters"];
  params.erase("order");
  params["smoothness"].erase("segments");
  params["smoothness"]["outer"] = 2.0;
  const Session back = parse_session_text(j.dump(), "s.json");
  EXPECT_EQ(back.current.parameters().settings.order, EditParameters().settings.order);
  EXPECT_EQ(back.current.parameters().settings.smoothness.outer, 2.0);
}

}  // namespace
}  // namespace freeform::editor
