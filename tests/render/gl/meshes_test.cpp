#include "render/gl/meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace clothsim {
namespace {

TEST(Meshes, UnitSphereVerticesLieOnTheSphereWithOutwardNormals) {
  const Mesh m = make_unit_sphere(16, 8);
  ASSERT_EQ(m.positions.size(), m.normals.size());
  for (std::size_t i = 0; i < m.positions.size(); i += 3) {
    const double r = std::sqrt(m.positions[i] * m.positions[i] + m.positions[i + 1] * m.positions[i + 1] +
                                m.positions[i + 2] * m.positions[i + 2]);
    EXPECT_NEAR(r, 1.0, 1e-6);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[i + k], m.positions[i + k]);
  }
}

TEST(Meshes, UnitSphereTrianglesAreCounterClockwiseFromOutsideAndCoverIt) {
  const int slices = 16, stacks = 8;
  const Mesh m = make_unit_sphere(slices, stacks);
  // Two triangles per quad, one per quad at each pole row.
  EXPECT_EQ(m.triangles.size(), 3u * (2 * slices * (stacks - 2) + 2 * slices));
  double area = 0.0;
  const auto& p = m.positions;
  for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
    const std::uint32_t a = m.triangles[t], b = m.triangles[t + 1], c = m.triangles[t + 2];
    const double e1[3] = {p[3 * b] - p[3 * a], p[3 * b + 1] - p[3 * a + 1], p[3 * b + 2] - p[3 * a + 2]};
    const double e2[3] = {p[3 * c] - p[3 * a], p[3 * c + 1] - p[3 * a + 1], p[3 * c + 2] - p[3 * a + 2]};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double centroid[3] = {p[3 * a] + p[3 * b] + p[3 * c], p[3 * a + 1] + p[3 * b + 1] + p[3 * c + 1],
                                p[3 * a + 2] + p[3 * b + 2] + p[3 * c + 2]};
    EXPECT_GT(n[0] * centroid[0] + n[1] * centroid[1] + n[2] * centroid[2], 0.0) << "triangle " << t / 3;
    area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  EXPECT_NEAR(area, 4.0 * M_PI, 0.1 * 4.0 * M_PI);  // a closed surface, slightly inside the sphere
  EXPECT_LT(area, 4.0 * M_PI);
}

// The outline of a sphere `slices` facets round lies radius (1 - cos(pi / slices)) inside the
// circle at worst: what sphere_slices bounds.
double outline_error_px(double radius_px, int slices) { return radius_px * (1.0 - std::cos(M_PI / slices)); }

TEST(Meshes, SphereSlicesAreTheFewestWhoseOutlineStraysAQuarterPixelAtMost) {
  for (float r = 1.f; r < 1500.f; r *= 1.07f) {
    const int n = sphere_slices(r);
    EXPECT_EQ(n % 4, 0) << r;
    EXPECT_GE(n, 12);
    EXPECT_LE(n, 128);
    if (n < 128) {
      EXPECT_LE(outline_error_px(r, n), kSphereOutlineErrorPx) << r << " px, " << n << " slices";
    }
    if (n > 12) {
      EXPECT_GT(outline_error_px(r, n - 4), kSphereOutlineErrorPx) << r << " px, " << n << " slices";
    }
    EXPECT_LE(n, sphere_slices(r * 1.07f)) << "larger spheres never get fewer facets";
  }
  EXPECT_EQ(sphere_slices(200.f), 64);  // the fixed mesh it replaces: 0.24 px at 200 px
  EXPECT_EQ(sphere_slices(0.1f), 12);
  EXPECT_EQ(sphere_slices(std::nanf("")), 12);
  EXPECT_EQ(sphere_slices(std::numeric_limits<float>::infinity()), 128);
  EXPECT_EQ(sphere_slices(100.f, 1.f), 24);  // a coarser bound: fewer facets
}

}  // namespace
}  // namespace clothsim
