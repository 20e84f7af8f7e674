// The Newton loop's SIMD passes against the scalar expressions they replace: the element-wise
// results to the bit, the sums within 1e-12 of the sums of their terms' sizes, immovable bodies
// (weight or mass 0) left out even where their vectors hold NaN, a NaN distance reported as
// NaN, and the same bits on every Highway target this CPU runs (lengths that leave every kind
// of tail).
#include "core/implicit/newton_kernels.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "core/kernel_test_support.h"

namespace clothsim {
namespace {

using testing::random_field;

// Positive weights with every fifth body's 0 (an immovable one).
Eigen::VectorXd weights(int B, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  Eigen::VectorXd w(B);
  for (int i = 0; i < B; ++i) w[i] = i % 5 == 3 ? 0.0 : u(rng);
  return w;
}

TEST(NewtonKernels, MatchTheScalarExpressionsOnEveryLength) {
  for (const int B : {1, 2, 3, 5, 8, 13, 16, 17, 625, 4096}) {
    SCOPED_TRACE(B);
    const std::size_t n = 3 * static_cast<std::size_t>(B);
    const Eigen::Matrix3Xd dv = random_field(B, 1), r = random_field(B, 2), a = random_field(B, 3), b = random_field(B, 4),
                           c = random_field(B, 5);
    const Eigen::VectorXd w = weights(B, 6);

    double ref = 0.0, size = 0.0;
    for (int i = 0; i < B; ++i)
      if (w[i] != 0.0) ref += dv.col(i).squaredNorm() * w[i];
    EXPECT_LE(std::abs(simd_weighted_norm2(w.data(), dv.data(), B) - ref), 1e-12 * ref);

    ref = 0.0;
    for (int i = 0; i < B; ++i)
      if (w[i] != 0.0) ref += (w[i] * dv.col(i) - r.col(i)).squaredNorm();
    EXPECT_LE(std::abs(simd_impulse_norm2(w.data(), dv.data(), r.data(), B) - ref), 1e-12 * ref);

    double miss[3] = {-1.0, -1.0, -1.0};
    simd_guess_misses(dv.data(), a.data(), b.data(), c.data(), n, miss);
    const Eigen::Matrix3Xd line = 2.0 * a - b, parabola = 3.0 * (a - b) + c;
    EXPECT_LE(std::abs(miss[0] - (dv - a).squaredNorm()), 1e-12 * (dv - a).squaredNorm());
    EXPECT_LE(std::abs(miss[1] - (dv - line).squaredNorm()), 1e-12 * (dv - line).squaredNorm());
    EXPECT_LE(std::abs(miss[2] - (dv - parabola).squaredNorm()), 1e-12 * (dv - parabola).squaredNorm());
    // Without the oldest step the parabola's distance is left as it was; the others are the same.
    double no_parabola[3] = {-1.0, -1.0, -1.0};
    simd_guess_misses(dv.data(), a.data(), b.data(), nullptr, n, no_parabola);
    EXPECT_EQ(no_parabola[0], miss[0]);
    EXPECT_EQ(no_parabola[1], miss[1]);
    EXPECT_EQ(no_parabola[2], -1.0);
    // Without the older steps only the orders they allow are written.
    double only_last[3] = {-1.0, -1.0, -1.0};
    simd_guess_misses(dv.data(), a.data(), nullptr, c.data(), n, only_last);
    EXPECT_EQ(only_last[0], miss[0]);
    EXPECT_EQ(only_last[1], -1.0);
    EXPECT_EQ(only_last[2], -1.0);

    size = (dv - a).colwise().squaredNorm().maxCoeff();
    EXPECT_EQ(simd_max_distance2(dv.data(), a.data(), B), size);  // a maximum: exact

    Eigen::Matrix3Xd x = a, v = b, x_ref = a, v_ref = b;
    v_ref += dv;
    x_ref += 0.01 * v_ref;
    simd_finish_step(x.data(), v.data(), dv.data(), 0.01, n);
    EXPECT_EQ(v, v_ref);
    EXPECT_EQ(x, x_ref);
  }
}

TEST(NewtonKernels, LeaveOutImmovableBodiesAndReportNaNDistances) {
  const int B = 21;
  Eigen::Matrix3Xd dv = random_field(B, 7), r = random_field(B, 8);
  const Eigen::VectorXd w = weights(B, 9);  // body 3, 8, 13, 18 immovable
  const double clean = simd_weighted_norm2(w.data(), dv.data(), B);
  const double clean_impulse = simd_impulse_norm2(w.data(), dv.data(), r.data(), B);
  dv.col(8).setConstant(std::numeric_limits<double>::quiet_NaN());  // an immovable body's: left out
  r.col(8).setConstant(std::numeric_limits<double>::infinity());
  EXPECT_EQ(simd_weighted_norm2(w.data(), dv.data(), B), clean);
  EXPECT_EQ(simd_impulse_norm2(w.data(), dv.data(), r.data(), B), clean_impulse);
  dv(1, 9) = std::numeric_limits<double>::quiet_NaN();  // a movable body's: it shows
  EXPECT_TRUE(std::isnan(simd_weighted_norm2(w.data(), dv.data(), B)));

  const Eigen::Matrix3Xd y0 = random_field(B, 10);
  for (const int at : {0, 9, 16, 20}) {  // in a vector and in the tail, on any target
    Eigen::Matrix3Xd y = y0;
    y(2, at) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(std::isnan(simd_max_distance2(y.data(), y0.data(), B))) << at;
  }
  EXPECT_EQ(simd_max_distance2(y0.data(), y0.data(), 0), 0.0);
}

TEST(NewtonKernels, EveryTargetGivesTheSameBits) {
  const int B = 37;
  const std::size_t n = 3 * B;
  const Eigen::Matrix3Xd dv = random_field(B, 11), r = random_field(B, 12), a = random_field(B, 13), b = random_field(B, 14),
                         c = random_field(B, 15);
  const Eigen::VectorXd w = weights(B, 16);
  struct Bits {
    double norm, impulse, distance, miss[3];
    Eigen::Matrix3Xd x, v;
  };
  const auto run = [&] {
    Bits out{0, 0, 0, {0, 0, 0}, a, b};
    out.norm = simd_weighted_norm2(w.data(), dv.data(), B);
    out.impulse = simd_impulse_norm2(w.data(), dv.data(), r.data(), B);
    out.distance = simd_max_distance2(dv.data(), c.data(), B);
    simd_guess_misses(dv.data(), a.data(), b.data(), c.data(), n, out.miss);
    simd_finish_step(out.x.data(), out.v.data(), dv.data(), 0.3, n);
    return out;
  };
  const Bits first = run();
  const std::string targets = testing::for_each_highway_target([&](const char* target) {
    const Bits got = run();
    EXPECT_EQ(std::memcmp(&got.norm, &first.norm, sizeof(double)), 0) << target;
    EXPECT_EQ(std::memcmp(&got.impulse, &first.impulse, sizeof(double)), 0) << target;
    EXPECT_EQ(std::memcmp(&got.distance, &first.distance, sizeof(double)), 0) << target;
    EXPECT_EQ(std::memcmp(got.miss, first.miss, sizeof first.miss), 0) << target;
    EXPECT_EQ(std::memcmp(got.x.data(), first.x.data(), sizeof(double) * n), 0) << target;
    EXPECT_EQ(std::memcmp(got.v.data(), first.v.data(), sizeof(double) * n), 0) << target;
  });
  EXPECT_FALSE(targets.empty());
}

}  // namespace
}  // namespace clothsim
