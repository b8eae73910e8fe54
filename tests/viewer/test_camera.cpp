// GL-free camera tests: view presets, look-at, projection, fitting, --camera parsing.
#include "viewer/camera.h"

#include "freeform/common/error.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace freeform::viewer;

namespace {

// World point -> normalized device coordinates.
Eigen::Vector3d ndc(const Camera& c, double aspect, const Eigen::Vector3d& p) {
  const Eigen::Vector4d q = c.projection(aspect) * c.view() * p.homogeneous();
  return q.head<3>() / q.w();
}

std::vector<Eigen::Vector3d> corners(const BoundingBox& b) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 8; ++i)
    out.emplace_back(i & 1 ? b.max.x() : b.min.x(), i & 2 ? b.max.y() : b.min.y(), i & 4 ? b.max.z() : b.min.z());
  return out;
}

}  // namespace

TEST(Camera, PresetDirectionsAndUp) {
  const auto dir = [](const char* name) { return preset_direction(*parse_view_preset(name)); };
  EXPECT_TRUE(dir("front").isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_TRUE(dir("back").isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_TRUE(dir("left").isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_TRUE(dir("right").isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(dir("top").isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(dir("bottom").isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_NEAR(dir("iso").norm(), 1.0, 1e-12);
  EXPECT_FALSE(parse_view_preset("diagonal").has_value());
  for (const char* name : {"front", "back", "left", "right", "top", "bottom", "iso"}) {
    const ViewPreset p = *parse_view_preset(name);
    EXPECT_GT(preset_up(p).cross(preset_direction(p)).norm(), 0.5) << name;  // up not along the view
  }
}

TEST(Camera, YUpPresets) {
  EXPECT_TRUE(preset_direction(ViewPreset::Front, UpAxis::Y).isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(preset_direction(ViewPreset::Top, UpAxis::Y).isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_TRUE(preset_direction(ViewPreset::Right, UpAxis::Y).isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(preset_up(ViewPreset::Front, UpAxis::Y).isApprox(Eigen::Vector3d(0, 1, 0)));
  const BoundingBox box{{-1, -1, -1}, {1, 1, 1}};
  const Camera f = fit_view(box, ViewPreset::Front, 1.0, 1.08, UpAxis::Y);
  EXPECT_GT(ndc(f, 1.0, {0, 0.5, 0}).y(), 0.05);  // +y is up on screen
  EXPECT_GT(ndc(f, 1.0, {0.5, 0, 0}).x(), 0.05);  // +x is to the right
}

TEST(Camera, LookAtMapsTargetToAxisAndUpToScreenUp) {
  Camera c;
  c.eye = {1, 2, 3};
  c.target = {1, 2, -1};
  c.up = {0, 1, 0};
  const Eigen::Matrix4d v = c.view();
  const Eigen::Vector4d t = v * c.target.homogeneous();
  EXPECT_NEAR(t.x(), 0, 1e-12);
  EXPECT_NEAR(t.y(), 0, 1e-12);
  EXPECT_NEAR(t.z(), -4, 1e-12);  // in front of the camera: negative z
  const Eigen::Vector4d u = v * (c.target + Eigen::Vector3d(0, 1, 0)).homogeneous();
  EXPECT_GT(u.y(), 0.9);
  // Rigid: the rotation block is orthonormal.
  EXPECT_TRUE((v.topLeftCorner<3, 3>() * v.topLeftCorner<3, 3>().transpose()).isIdentity(1e-12));
}

TEST(Camera, PresetScreenAxes) {
  const BoundingBox box{{-1, -1, -1}, {1, 1, 1}};
  // Front view: +x is to the right, +z is up on screen.
  const Camera f = fit_view(box, ViewPreset::Front, 1.0);
  EXPECT_GT(ndc(f, 1.0, {0.5, 0, 0}).x(), 0.05);
  EXPECT_GT(ndc(f, 1.0, {0, 0, 0.5}).y(), 0.05);
  // Top view: +x right, +y up on screen.
  const Camera t = fit_view(box, ViewPreset::Top, 1.0);
  EXPECT_GT(ndc(t, 1.0, {0.5, 0, 0}).x(), 0.05);
  EXPECT_GT(ndc(t, 1.0, {0, 0.5, 0}).y(), 0.05);
  // Nearer to the eye = smaller depth.
  EXPECT_LT(ndc(t, 1.0, {0, 0, 0.9}).z(), ndc(t, 1.0, {0, 0, -0.9}).z());
}

TEST(Camera, FitViewContainsTheBoxForEveryPresetAndAspect) {
  const BoundingBox box{{-3, 0.5, 10}, {5, 2.5, 11}};
  for (const char* name : {"front", "back", "left", "right", "top", "bottom", "iso"})
    for (const double aspect : {0.5, 1.0, 4.0 / 3.0, 2.5}) {
      const Camera c = fit_view(box, *parse_view_preset(name), aspect);
      double extent = 0.0;
      for (const Eigen::Vector3d& p : corners(box)) {
        const Eigen::Vector3d q = ndc(c, aspect, p);
        EXPECT_LE(std::abs(q.x()), 1.0) << name << " aspect " << aspect;
        EXPECT_LE(std::abs(q.y()), 1.0) << name << " aspect " << aspect;
        EXPECT_GT(q.z(), -1.0) << name;  // inside the near and far planes
        EXPECT_LT(q.z(), 1.0) << name;
        extent = std::max({extent, std::abs(q.x()), std::abs(q.y())});
      }
      EXPECT_GT(extent, 0.9) << name << " aspect " << aspect << ": the box should fill a good part of the view";
      EXPECT_TRUE(ndc(c, aspect, box.center()).head<2>().isZero(1e-9)) << name;  // centred
    }
}

TEST(Camera, ParseSpecOverridesOnlyTheGivenKeys) {
  Camera base;
  base.fov_y_deg = 25;
  const Camera c = parse_camera_spec("eye=1,2,3; target=0,0,0.5 ;up=0,1,0;fov=40", base);
  EXPECT_TRUE(c.eye.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(c.target.isApprox(Eigen::Vector3d(0, 0, 0.5)));
  EXPECT_TRUE(c.up.isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_EQ(c.fov_y_deg, 40);
  const Camera d = parse_camera_spec("fov=10", base);
  EXPECT_EQ(d.fov_y_deg, 10);
  EXPECT_TRUE(d.eye.isApprox(base.eye));
  EXPECT_TRUE(parse_camera_spec("", base).eye.isApprox(base.eye));
}

TEST(Camera, ParseSpecRejectsBadInputWithClearMessages) {
  const Camera base;
  const auto msg = [&](const char* spec) {
    try {
      parse_camera_spec(spec, base);
    } catch (const freeform::InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(msg("eye=1,2").find("three numbers"), std::string::npos);
  EXPECT_NE(msg("eye=1,2,x").find("\"eye\""), std::string::npos);
  EXPECT_NE(msg("pos=1,2,3").find("unknown key \"pos\""), std::string::npos);
  EXPECT_NE(msg("fov=200").find("fov"), std::string::npos);
  EXPECT_NE(msg("fov").find("key=value"), std::string::npos);
  EXPECT_NE(msg("up=0,0,0").find("zero"), std::string::npos);
  EXPECT_NE(msg("eye=0,0,0;target=0,0,0").find("differ"), std::string::npos);
  EXPECT_NE(msg("fov=nan").find("fov"), std::string::npos);
}

TEST(Camera, DegenerateUpStillGivesAnOrthonormalView) {
  Camera c;
  c.eye = {0, 0, 5};
  c.target = {0, 0, 0};
  c.up = {0, 0, 1};  // parallel to the view direction
  const Eigen::Matrix4d v = c.view();
  EXPECT_TRUE(v.allFinite());
  EXPECT_TRUE((v.topLeftCorner<3, 3>() * v.topLeftCorner<3, 3>().transpose()).isIdentity(1e-12));
}
