// The contact search's SIMD screen against the scalar test it stands for (step_contacts.cpp's
// NearColliders::maybe), on every end-position form and every Highway target.
#include "core/implicit/contact_kernels.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/kernel_test_support.h"

namespace clothsim {
namespace {

TEST(ContactKernels, ScreenFlagsExactlyThePositionsNearAColliderOnEveryTarget) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double h = 0.01;
  const Eigen::Matrix3d centre = (Eigen::Matrix3d() << 0, 1, -1, 0, 0.5, 0, 0, 0, 1).finished();
  const double bound2[3] = {1.0, 0.25, 0.09};
  for (const int n : {1, 5, 8, 13, 200}) {
    Eigen::Matrix3Xd x(3, n), v(3, n), g(3, n);
    for (int p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) x(c, p) = u(rng), v(c, p) = 10 * u(rng), g(c, p) = u(rng);
    for (const double ground : {-1.5, -std::numeric_limits<double>::infinity()}) {
      NearScreen screen;
      screen.centre = centre.data();
      screen.bound2 = bound2;
      screen.spheres = 3;
      screen.ground = ground;
      const auto expected = [&](const Eigen::Vector3d& at) {
        bool near = at.y() < ground;
        for (int s = 0; s < 3; ++s) {
          const Eigen::Vector3d d = at - centre.col(s);
          near = near || (d.x() * d.x() + d.y() * d.y()) + d.z() * d.z() < bound2[s];
        }
        return near;
      };
      testing::for_each_highway_target([&](const char* target) {
        std::vector<std::int32_t> at_x, at_v, at_g, want_x, want_v, want_g;
        near_screen(screen, x.data(), nullptr, nullptr, h, n, at_x);
        near_screen(screen, x.data(), v.data(), nullptr, h, n, at_v);
        near_screen(screen, x.data(), v.data(), g.data(), h, n, at_g);
        for (int p = 0; p < n; ++p) {
          if (expected(x.col(p))) want_x.push_back(p);
          if (expected(x.col(p) + h * v.col(p))) want_v.push_back(p);
          if (expected(x.col(p) + h * (v.col(p) + g.col(p)))) want_g.push_back(p);
        }
        EXPECT_EQ(at_x, want_x) << target;
        EXPECT_EQ(at_v, want_v) << target;
        EXPECT_EQ(at_g, want_g) << target;
      });
    }
  }
}

}  // namespace
}  // namespace clothsim
