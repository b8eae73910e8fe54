// In-process rendering through the headless EGL context: the library path the editor uses.
// Fails (never skips) when no EGL/OpenGL 3.3 context can be made: CI must be able to render.
#include "pixel_stats.h"

#include "freeform/mesh/generators.h"
#include "viewer/egl_context.h"
#include "viewer/gl_util.h"
#include "viewer/offscreen.h"
#include "viewer/region_colors.h"
#include "viewer/render_scene.h"
#include "viewer/renderer.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

using namespace freeform;
using namespace freeform::viewer;
using freeform::test::classify;
using freeform::test::PixelClass;

namespace {

std::unique_ptr<EglContext> context_or_fail() {
  try {
    auto c = std::make_unique<EglContext>();
    std::printf("EGL: %s (DISPLAY=%s)\n", c->description().c_str(), std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset");
    return c;
  } catch (const RenderError& e) {
    ADD_FAILURE() << "no headless OpenGL context (install the packages of scripts/bootstrap.sh): " << e.what();
    return nullptr;
  }
}

}  // namespace

TEST(RenderGl, HeadlessContextIsCore33) {
  const auto ctx = context_or_fail();
  ASSERT_TRUE(ctx);
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 33);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
}

TEST(RenderGl, DrawsSceneColoursOnBackgroundAndUpdatesInPlace) {
  const auto ctx = context_or_fail();
  ASSERT_TRUE(ctx);
  const int w = 160, h = 120;
  RenderScene scene = make_scene(make_plane(10, 10), Rgb{0.25f, 0.8f, 0.3f});
  OffscreenTarget target(w, h);
  Renderer renderer;
  renderer.upload(scene);
  const Camera cam = fit_view(scene.bounds, ViewPreset::Top, static_cast<double>(w) / h);
  target.bind();
  renderer.draw(cam, w, h);
  std::vector<std::uint8_t> px = target.read_rgba();
  ASSERT_EQ(px.size(), static_cast<std::size_t>(w * h * 4));
  EXPECT_EQ(classify(&px[4 * (h / 2 * w + w / 2)]), PixelClass::Green);   // centre: the plane
  EXPECT_EQ(classify(&px[0]), PixelClass::Background);                   // corner: white
  // Facing the headlight, the plane is lit near full strength (not black, not washed out).
  EXPECT_GT(px[4 * (h / 2 * w + w / 2) + 1], 150);

  // Editor path: recolour and move without re-uploading topology.
  set_colors(scene, std::vector<Rgb>(static_cast<std::size_t>(scene.n_vertices()), Rgb{0.3f, 0.5f, 0.95f}));
  renderer.update_colors(scene);
  VertexData<Vec3> moved(static_cast<std::size_t>(scene.n_vertices()), Vec3::Zero());
  for (int v = 0; v < scene.n_vertices(); ++v)
    moved[Vertex(v)] = Vec3(scene.positions[3 * v] + 5.0, scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
  update_geometry(scene, moved);
  renderer.update_geometry(scene);
  renderer.draw(cam, w, h, DrawOptions{{0.93f, 0.94f, 0.96f}, false, {}});
  px = target.read_rgba();
  EXPECT_EQ(px[0], static_cast<std::uint8_t>(0.93f * 255 + 0.5f));  // light background
  int blue = 0;
  for (int i = 0; i < w * h; ++i) blue += classify(&px[4 * i]) == PixelClass::Blue;
  EXPECT_EQ(blue, 0) << "the plane moved out of the view";
}

TEST(RenderGl, WireframeDrawsDarkEdges) {
  const auto ctx = context_or_fail();
  ASSERT_TRUE(ctx);
  const int w = 200, h = 200;
  const RenderScene scene = make_scene(make_plane(8, 8), kPlainColor);
  OffscreenTarget target(w, h, 0);
  Renderer renderer;
  renderer.upload(scene);
  const Camera cam = fit_view(scene.bounds, ViewPreset::Top, 1.0);
  target.bind();
  const auto dark = [&](const DrawOptions& o) {
    renderer.draw(cam, w, h, o);
    const std::vector<std::uint8_t> px = target.read_rgba();
    int n = 0;
    for (int i = 0; i < w * h; ++i) n += px[4 * i] < 80 && px[4 * i + 1] < 80 && px[4 * i + 2] < 80;
    return n;
  };
  EXPECT_EQ(dark({}), 0);
  DrawOptions wire;
  wire.wireframe = true;
  EXPECT_GT(dark(wire), 9 * 150);  // 9 + 9 grid lines plus diagonals, each ~150 px long
}

TEST(RenderGl, PngRoundTrip) {
  std::vector<std::uint8_t> rgba(4 * 3 * 2);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<std::uint8_t>(i * 10);
  const test::Image img = test::decode_png(encode_png(rgba, 3, 2));
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.rgba, rgba);
  EXPECT_THROW(encode_png(rgba, 4, 2), InvalidInput);
}
