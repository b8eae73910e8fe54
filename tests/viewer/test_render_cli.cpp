// End-to-end tests of `freeform render`, checked by pixel statistics of the decoded PNG:
// region colours where the regions project, coverage of the fitted view, exit codes, and no
// output file on any error. Headless (EGL), so they run without a display; no skipping.
#include "pixel_stats.h"

#include "cli/cli_runner.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <tuple>

using namespace freeform;
using namespace freeform::test;

namespace {

// 41 x 41 grid on the unit square (z = 0); support disk r = 0.35 and handle r = 0.1 at the centre.
struct Plane {
  ScratchDir dir;
  std::filesystem::path mesh = dir / "plane.off";
  std::filesystem::path edit = dir / "edit.json";
  Plane() {
    write_mesh(mesh.string(), make_plane(40, 40));
    write_text(edit, R"({
      "order": 2,
      "support": {"geodesic": {"center": [0.5, 0.5, 0], "radius": 0.35}},
      "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.1}},
                   "transform": {"translate": [0, 0, 0.15]}}]
    })");
  }
};

const char* kTopCamera = "eye=0.5,0.5,3;target=0.5,0.5,0;up=0,1,0;fov=25";

viewer::Camera top_camera() {
  viewer::Camera c;
  c.eye = {0.5, 0.5, 3};
  c.target = {0.5, 0.5, 0};
  c.up = {0, 1, 0};
  c.fov_y_deg = 25;
  return c;
}

struct Counts {
  int total = 0, blue = 0, green = 0, gray = 0, background = 0, other = 0;
  void add(PixelClass c) {
    ++total;
    blue += c == PixelClass::Blue;
    green += c == PixelClass::Green;
    gray += c == PixelClass::Gray;
    background += c == PixelClass::Background;
    other += c == PixelClass::Other;
  }
};

std::string describe(const Counts& c) {
  return std::to_string(c.total) + " px: blue " + std::to_string(c.blue) + ", green " + std::to_string(c.green) +
         ", gray " + std::to_string(c.gray) + ", background " + std::to_string(c.background) + ", other " +
         std::to_string(c.other);
}

}  // namespace

// Top view of the original plane: an annulus 0.14 < r < 0.31 around the centre is blue (support),
// r < 0.06 green (handle), the corners gray (fixed), outside the square white.
TEST(CliRender, RegionColoursWhereTheRegionsProject) {
  const Plane s;
  const auto out = s.dir / "regions.png";
  const int w = 400, h = 400;
  const CliRun r = freeform_cli("render " + q(s.mesh) + " --edit " + q(s.edit) + " --show original --size 400x400 -o " +
                                q(out) + " --camera '" + kTopCamera + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image img = load_png(out.string());
  ASSERT_EQ(img.width, w);
  ASSERT_EQ(img.height, h);
  const viewer::Camera cam = top_camera();
  const Eigen::Vector2d c = project(cam, w, h, {0.5, 0.5, 0});
  const double px_per_unit = (project(cam, w, h, {1.5, 0.5, 0}) - c).norm();
  Counts annulus, centre, corners, outside;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = (x + 0.5 - c.x()) / px_per_unit, v = (c.y() - (y + 0.5)) / px_per_unit;  // world offsets
      const double radius = std::hypot(u, v);
      const PixelClass k = classify(img.at(x, y));
      if (std::abs(u) > 0.51 || std::abs(v) > 0.51) outside.add(k);
      else if (radius < 0.06) centre.add(k);
      else if (radius > 0.14 && radius < 0.31) annulus.add(k);
      else if (std::abs(u) > 0.42 && std::abs(v) > 0.42 && std::abs(u) < 0.49 && std::abs(v) < 0.49) corners.add(k);
    }
  ASSERT_GT(annulus.total, 1000);
  ASSERT_GT(centre.total, 100);
  ASSERT_GT(corners.total, 100);
  ASSERT_GT(outside.total, 1000);
  EXPECT_GT(annulus.blue, 0.97 * annulus.total) << describe(annulus);
  EXPECT_GT(centre.green, 0.97 * centre.total) << describe(centre);
  EXPECT_GT(corners.gray, 0.97 * corners.total) << describe(corners);
  EXPECT_GT(outside.background, 0.99 * outside.total) << describe(outside);
}

// Iso view, same fitted frame for both (the union of original and deformed bounds): the
// handle (green) is drawn higher in the deformed render than in the original one.
TEST(CliRender, DeformedShapeShowsTheLiftedHandle) {
  const Plane s;
  const auto green_centroid_row = [&](const std::string& show) {
    const auto out = s.dir / (show + ".png");
    const CliRun r = freeform_cli("render " + q(s.mesh) + " --edit " + q(s.edit) + " --show " + show +
                                  " --view iso --size 320x240 --background light -o " + q(out));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const Image img = load_png(out.string());
    EXPECT_EQ(img.width, 320);
    double sum = 0;
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (classify(img.at(x, y)) == PixelClass::Green) {
          sum += y;
          ++n;
        }
    EXPECT_GT(n, 100) << show << ": no handle pixels";
    // Light background: (0.93, 0.94, 0.96) * 255.
    if (img.width > 0) {
      EXPECT_EQ(img.at(0, 0)[0], 237);
      EXPECT_EQ(img.at(0, 0)[2], 245);
    }
    return n > 0 ? sum / n : 0.0;
  };
  const double original = green_centroid_row("original"), deformed = green_centroid_row("deformed");
  EXPECT_GT(original - deformed, 10.0) << "lifted by 0.15 of a unit square that spans ~250 px";
}

// A C0 segment on the right stretch of the outer boundary (k = 3): with the band shown, red
// pixels lie in the right half of the plane and violet (C2) ones in the left, plus the legend
// in the lower left; --band off shows neither.
TEST(CliRender, SmoothnessBandColoursAndLegend) {
  const Plane s;
  const auto edit = s.dir / "segments.json";
  write_text(edit, R"({
    "order": 3, "multiresolution": false,
    "support": {"geodesic": {"center": [0.5, 0.5, 0], "radius": 0.35}},
    "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.1}}}],
    "smoothness": {"segments": [{"region": {"sphere": {"center": [0.9, 0.5, 0], "radius": 0.3}}, "value": 0}]}
  })");
  const int w = 400, h = 400;
  const viewer::Camera cam = top_camera();
  const double centre_x = project(cam, w, h, {0.5, 0.5, 0}).x();
  struct Found {
    int red_right = 0, red_left = 0, violet_left = 0, violet_right = 0, legend = 0;
  };
  const auto run = [&](const std::string& band) {
    const auto out = s.dir / ("band-" + band + ".png");
    const CliRun r = freeform_cli("render " + q(s.mesh) + " --edit " + q(edit) + " --band " + band +
                                  " --size 400x400 --samples 0 -o " + q(out) + " --camera '" + kTopCamera + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const Image img = load_png(out.string());
    Found f;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const std::uint8_t* p = img.at(x, y);
        const bool red = p[0] > 150 && p[1] < 90 && p[2] < 90;
        const bool violet = p[0] > 90 && p[2] > 150 && p[1] < 110 && p[2] > p[1] + 60 && p[0] > p[1] + 30;
        if (y > h - 45 && x < 160) {  // the legend's corner (outside the plane in this view)
          f.legend += red || violet;
          continue;
        }
        (x > centre_x ? f.red_right : f.red_left) += red;
        (x < centre_x ? f.violet_left : f.violet_right) += violet;
      }
    return f;
  };
  const Found on = run("auto");
  EXPECT_GT(on.red_right, 200);
  EXPECT_EQ(on.red_left, 0);
  EXPECT_GT(on.violet_left, 200);
  EXPECT_GT(on.legend, 100);
  const Found off = run("off");
  EXPECT_EQ(off.red_right + off.red_left + off.violet_left + off.violet_right + off.legend, 0);
}

// No edit, top view fitted to the bounding box: the covered pixels fill the projected square.
TEST(CliRender, CoverageMatchesTheProjectedBoundingBox) {
  const Plane s;
  const auto out = s.dir / "plain.png";
  const int w = 320, h = 240;
  const CliRun r = freeform_cli("render " + q(s.mesh) + " --view top --size 320x240 --samples 0 -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image img = load_png(out.string());
  ASSERT_EQ(img.width, w);
  ASSERT_EQ(img.height, h);
  const viewer::BoundingBox box{{0, 0, 0}, {1, 1, 0}};
  const viewer::Camera cam = viewer::fit_view(box, viewer::ViewPreset::Top, static_cast<double>(w) / h);
  const Eigen::Vector2d lo = project(cam, w, h, {0, 1, 0}), hi = project(cam, w, h, {1, 0, 0});  // top-left, bottom-right
  int covered = 0, covered_outside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (classify(img.at(x, y)) == PixelClass::Background) continue;
      ++covered;
      if (x + 0.5 < lo.x() - 1 || x + 0.5 > hi.x() + 1 || y + 0.5 < lo.y() - 1 || y + 0.5 > hi.y() + 1) ++covered_outside;
    }
  const double expected = (hi.x() - lo.x()) * (hi.y() - lo.y());
  EXPECT_NEAR(covered, expected, 0.02 * expected);
  EXPECT_EQ(covered_outside, 0);
  // The fit uses the view well: the square spans most of the image height.
  EXPECT_GT(hi.y() - lo.y(), 0.6 * h);
}

TEST(CliRender, TimingsAndWireframe) {
  const Plane s;
  const auto out = s.dir / "wire.png";
  const CliRun r = freeform_cli("render " + q(s.mesh) + " --wireframe --timings --view iso -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("upload"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("draw"), std::string::npos) << r.out;
  const Image img = load_png(out.string());
  ASSERT_EQ(img.width, 640);  // the default size
  ASSERT_EQ(img.height, 480);
  int dark = 0;
  for (int i = 0; i < img.width * img.height; ++i) dark += img.rgba[4 * i] < 90 && img.rgba[4 * i + 2] < 90;
  EXPECT_GT(dark, 2000) << "wireframe edges";
}

TEST(CliRender, ErrorsLeaveNoOutput) {
  const Plane s;
  const auto out = s.dir / "bad.png";
  const auto expect = [&](const std::string& args, int code, const std::string& message) {
    const CliRun r = freeform_cli("render " + args + " -o " + q(out));
    EXPECT_EQ(r.exit_code, code) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << args;
  };
  expect(q(s.mesh) + " --size 640", 2, "WIDTHxHEIGHT");
  expect(q(s.mesh) + " --size 0x10", 2, "WIDTHxHEIGHT");
  expect(q(s.mesh) + " --view diagonal", 2, "--view");
  expect(q(s.mesh) + " --camera 'eye=1,2'", 2, "three numbers");
  expect(q(s.mesh) + " --camera 'zoom=2'", 2, "unknown key");
  expect(q(s.mesh) + " --show original", 2, "needs --edit");
  expect(q(s.dir / "missing.off"), 1, "missing.off");
  write_text(s.dir / "broken.json", "{\"support\": 3}");
  expect(q(s.mesh) + " --edit " + q(s.dir / "broken.json"), 1, "broken.json");
  const CliRun wrong_ext = freeform_cli("render " + q(s.mesh) + " -o " + q(s.dir / "x.jpg"));
  EXPECT_EQ(wrong_ext.exit_code, 2) << wrong_ext.err;
}

// No EGL driver (GLVND finds no vendor library): a clear message, exit code 3, no file.
TEST(CliRender, NoEglDriverFailsClearly) {
  const Plane s;
  const auto out = s.dir / "noegl.png";
  ::setenv("__EGL_VENDOR_LIBRARY_FILENAMES", (s.dir / "no-such-vendor.json").c_str(), 1);
  const CliRun r = freeform_cli("render " + q(s.mesh) + " -o " + q(out));
  ::unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("cannot render"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("EGL"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A mesh far from the origin (offset 5e6: float keeps ~0.5 units there) or beyond float's range
// (1e39) renders like the same mesh at the origin: the scene is recentred and rescaled before
// it becomes floats. A user camera is given in mesh coordinates.
TEST(CliRender, FarAndHugeMeshesRenderLikeTheMeshAtTheOrigin) {
  const Plane s;
  const auto render = [&](const std::string& name, double scale, double offset, const std::string& extra) {
    TriangleSoup soup = make_plane(40, 40);
    for (Vec3& p : soup.positions) p = p * scale + Vec3::Constant(offset);
    const auto mesh = s.dir / (name + ".off");
    write_mesh(mesh.string(), soup);
    const auto out = s.dir / (name + ".png");
    const CliRun r = freeform_cli("render " + q(mesh) + " --view top --size 160x120 --samples 0 --wireframe" + extra +
                                  " -o " + q(out));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return load_png(out.string());
  };
  const Image ref = render("ref", 1.0, 0.0, "");
  int covered = 0;
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) covered += classify(ref.at(x, y)) != PixelClass::Background;
  ASSERT_GT(covered, 160 * 120 / 4);
  for (const auto& [name, scale, offset] : {std::tuple{"far", 1.0, 5e6}, std::tuple{"huge", 1e39, 0.0},
                                           std::tuple{"far-huge", 1e39, 3e40}}) {
    const Image img = render(name, scale, offset, "");
    int differ = 0;
    for (int y = 0; y < ref.height; ++y)
      for (int x = 0; x < ref.width; ++x) differ += classify(img.at(x, y)) != classify(ref.at(x, y));
    EXPECT_LT(differ, 0.01 * covered) << name;  // the wireframe's grid lines land on the same pixels
  }
  // A camera in mesh coordinates, 5e6 away from the origin, sees the plane too.
  const Image cam = render("far-camera", 1.0, 5e6, " --camera 'eye=5000000.5,5000000.5,5000003;target=5000000.5,5000000.5,5000000;up=0,1,0'");
  int seen = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) seen += classify(cam.at(x, y)) != PixelClass::Background;
  EXPECT_GT(seen, 160 * 120 / 8);
}
