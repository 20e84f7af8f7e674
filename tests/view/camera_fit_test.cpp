// The automatic camera: every framed point and sphere projected through the camera it returns
// (an independent look-at and perspective, written out here) lies in the view, and the cloth
// fills it: at least half the width, or most of the height when the height is what limits.
#include "view/camera_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace clothsim {
namespace {

using P3 = std::array<float, 3>;

struct Ndc {
  double x, y, depth;
};

// gluLookAt + gluPerspective, as the renderer builds them, in doubles.
Ndc project(const RenderCamera& c, float aspect, P3 p) {
  const auto sub = [](P3 a, P3 b) { return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const auto dot = [](std::array<double, 3> a, std::array<double, 3> b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const auto cross = [](std::array<double, 3> a, std::array<double, 3> b) {
    return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const auto unit = [&](std::array<double, 3> a) {
    const double n = std::sqrt(dot(a, a));
    return std::array<double, 3>{a[0] / n, a[1] / n, a[2] / n};
  };
  const auto f = unit(sub(c.target, c.eye));
  const auto s = unit(cross(f, {c.up[0], c.up[1], c.up[2]}));
  const auto u = cross(s, f);
  const auto d = sub(p, c.eye);
  const double depth = dot(d, f), t = std::tan(c.fov_deg * 3.14159265358979 / 360.0);
  return {dot(d, s) / (depth * t * aspect), dot(d, u) / (depth * t), depth};
}

struct Extent {
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  bool in_front = true;
  void add(Ndc n) {
    x0 = std::min(x0, n.x), x1 = std::max(x1, n.x), y0 = std::min(y0, n.y), y1 = std::max(y1, n.y);
    in_front = in_front && n.depth > 0;
  }
  double width_share() const { return (x1 - x0) / 2; }   // of the view's width
  double height_share() const { return (y1 - y0) / 2; }
  bool inside() const { return in_front && x0 >= -1 && x1 <= 1 && y0 >= -1 && y1 <= 1; }
};

Extent cloth_extent(const RenderCamera& c, float aspect, const std::vector<P3>& cloth) {
  Extent e;
  for (const P3& p : cloth) e.add(project(c, aspect, p));
  return e;
}

// Everything: the cloth and a dense sampling of each sphere's surface.
Extent whole_extent(const RenderCamera& c, float aspect, const std::vector<P3>& cloth,
                    const std::vector<RenderSphere>& spheres) {
  Extent e = cloth_extent(c, aspect, cloth);
  for (const RenderSphere& s : spheres)
    for (int i = 0; i <= 60; ++i)
      for (int j = 0; j < 120; ++j) {
        const double theta = 3.14159265358979 * i / 60, phi = 2 * 3.14159265358979 * j / 120;
        e.add(project(c, aspect,
                      {static_cast<float>(s.center[0] + s.radius * std::sin(theta) * std::cos(phi)),
                       static_cast<float>(s.center[1] + s.radius * std::cos(theta)),
                       static_cast<float>(s.center[2] + s.radius * std::sin(theta) * std::sin(phi))}));
      }
  return e;
}

// An n x n grid over a square of side `size` centred at `centre`, horizontal (xz) or hanging (xy).
std::vector<P3> square(P3 centre, float size, bool vertical, int n = 11) {
  std::vector<P3> points;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float a = (static_cast<float>(i) / (n - 1) - 0.5f) * size, b = (static_cast<float>(j) / (n - 1) - 0.5f) * size;
      points.push_back(vertical ? P3{centre[0] + a, centre[1] + b, centre[2]} : P3{centre[0] + a, centre[1], centre[2] + b});
    }
  return points;
}

bool finite(const RenderCamera& c) {
  for (const auto* a : {&c.eye, &c.target})
    for (float v : *a)
      if (!std::isfinite(v)) return false;
  return std::isfinite(c.fov_deg);
}

class CameraFit : public ::testing::TestWithParam<float> {};  // the aspect: 1:1 and 16:9

TEST_P(CameraFit, AHorizontalSquareFillsMoreThanHalfTheWidthAndStaysInView) {
  const float aspect = GetParam();
  const auto cloth = square({0.f, 1.f, 0.f}, 4.f, false);
  const RenderCamera c = fit_camera(cloth, {}, aspect);
  const Extent e = cloth_extent(c, aspect, cloth);
  EXPECT_TRUE(e.inside());
  EXPECT_GE(e.width_share(), 0.5);
  EXPECT_NEAR(std::max({-e.x0, e.x1, -e.y0, e.y1}), 0.8, 1e-3) << "the limiting side at the fill";
}

TEST_P(CameraFit, AVerticalCurtainFillsHalfTheWidthOrMostOfTheHeight) {
  const float aspect = GetParam();
  const auto cloth = square({0.f, 1.f, 0.f}, 3.f, true);
  const RenderCamera c = fit_camera(cloth, {}, aspect);
  const Extent e = cloth_extent(c, aspect, cloth);
  EXPECT_TRUE(e.inside());
  EXPECT_GE(e.width_share(), 0.5);
  EXPECT_GE(e.height_share(), 0.5);
}

TEST_P(CameraFit, AClothAboveASphereIsFramedWithTheWholeSphere) {
  const float aspect = GetParam();
  const auto cloth = square({0.f, 1.f, 0.f}, 4.f, false);
  const std::vector<RenderSphere> spheres{RenderSphere{{0.f, 0.f, 0.f}, 1.f, {}}};
  const RenderCamera c = fit_camera(cloth, spheres, aspect);
  const Extent all = whole_extent(c, aspect, cloth, spheres);
  EXPECT_TRUE(all.inside());
  EXPECT_GE(cloth_extent(c, aspect, cloth).width_share(), 0.5);
  // Tight: the sphere's exact silhouette, not a loose bound, decides the fit.
  EXPECT_GT(std::max({-all.x0, all.x1, -all.y0, all.y1}), 0.79);
}

TEST_P(CameraFit, TheProjectedExtentIsCentred) {
  const float aspect = GetParam();
  const auto cloth = square({2.f, -1.f, 3.f}, 2.f, false);
  const RenderCamera c = fit_camera(cloth, {RenderSphere{{2.f, -1.6f, 3.f}, 0.5f, {}}}, aspect);
  const Extent e = whole_extent(c, aspect, cloth, {RenderSphere{{2.f, -1.6f, 3.f}, 0.5f, {}}});
  EXPECT_NEAR(e.x0 + e.x1, 0.0, 0.02);
  EXPECT_NEAR(e.y0 + e.y1, 0.0, 0.02);
}

INSTANTIATE_TEST_SUITE_P(Aspects, CameraFit, ::testing::Values(1.f, 16.f / 9.f));

TEST(CameraFit, LooksFromTheFrontAndAboveAsTheShippedScenesDo) {
  const auto cloth = square({0.f, 1.f, 0.f}, 4.f, false);
  const RenderCamera c = fit_camera(cloth, {}, 16.f / 9.f);
  EXPECT_LT(c.eye[2], c.target[2]) << "from -z towards +z, as drape's eye (0, 2, -10)";
  EXPECT_GT(c.eye[1], c.target[1]) << "above: a horizontal cloth is not seen edge-on";
  const double rise = std::atan2(c.eye[1] - c.target[1], std::hypot(c.eye[0] - c.target[0], c.eye[2] - c.target[2]));
  EXPECT_NEAR(rise * 180.0 / 3.14159265358979, 30.0, 0.01);
  EXPECT_NEAR(c.eye[0], c.target[0], 1e-4);
  // A positive azimuth swings the eye towards +x, as curtain.yaml's (6, 2.5, -7).
  CameraFitOptions swung;
  swung.azimuth_deg = 40.f;
  const RenderCamera d = fit_camera(cloth, {}, 16.f / 9.f, swung);
  EXPECT_GT(d.eye[0], d.target[0]);
  EXPECT_LT(d.eye[2], d.target[2]);
}

TEST(CameraFit, AFlatFrameArrayGivesTheSameCamera) {
  const auto cloth = square({0.f, 1.f, 0.f}, 4.f, false, 3);
  std::vector<float> flat;
  for (const P3& p : cloth) flat.insert(flat.end(), p.begin(), p.end());
  const RenderCamera a = fit_camera(cloth, {}, 1.5f), b = fit_camera(flat, {}, 1.5f);
  EXPECT_EQ(a.eye, b.eye);
  EXPECT_EQ(a.target, b.target);
}

TEST(CameraFit, DegenerateInputGivesAFiniteCameraThatSeesIt) {
  const std::vector<std::vector<P3>> cases = {
      {},                                             // nothing
      {{1.f, 2.f, 3.f}},                              // one point
      {{-1.f, 0.f, 0.f}, {1.f, 0.f, 0.f}},            // a line across the view
      {{0.f, 0.f, -1.f}, {0.f, 0.f, 1.f}},            // a line nearly along it
      {{0.f, -1.f, 0.f}, {0.f, 1.f, 0.f}},            // a vertical line
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const RenderCamera c = fit_camera(cases[i], {}, 16.f / 9.f);
    EXPECT_TRUE(finite(c)) << "case " << i;
    EXPECT_GT(std::hypot(c.eye[0] - c.target[0], c.eye[1] - c.target[1], c.eye[2] - c.target[2]), 1e-3) << "case " << i;
    EXPECT_TRUE(cloth_extent(c, 16.f / 9.f, cases[i]).inside()) << "case " << i;
  }
  const RenderCamera only_sphere = fit_camera(std::vector<P3>{}, {RenderSphere{{0.f, 0.f, 0.f}, 1.f, {}}}, 1.f);
  EXPECT_TRUE(finite(only_sphere));
  EXPECT_TRUE(whole_extent(only_sphere, 1.f, {}, {RenderSphere{{0.f, 0.f, 0.f}, 1.f, {}}}).inside());
}

}  // namespace
}  // namespace clothsim
