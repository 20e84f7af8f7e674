// The CG loop's SIMD passes against Eigen's expressions: the element-wise results to the bit,
// the sums within 1e-12 of the sums of their terms' sizes, and the same bits on every Highway
// target this CPU runs (lengths that leave every kind of tail).
#include "core/linear/cg_kernels.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <Eigen/Core>
#include <Eigen/LU>  // Matrix3d::inverse, the reference
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "core/kernel_test_support.h"

namespace clothsim {
namespace {

using testing::random_field;

// Symmetric positive definite 3 x 3 blocks, as structure of arrays (xx, yy, zz, xy, xz, yz).
std::vector<double> inverse_blocks(int B, unsigned seed, std::vector<Eigen::Matrix3d>& blocks) {
  const Eigen::Matrix3Xd r = random_field(3 * B, seed);
  std::vector<double> soa(6 * B);
  blocks.resize(B);
  for (int i = 0; i < B; ++i) {
    const Eigen::Matrix3d m = r.block<3, 3>(0, 3 * i);
    blocks[i] = m * m.transpose() + Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d& D = blocks[i];
    const double entry[6] = {D(0, 0), D(1, 1), D(2, 2), D(0, 1), D(0, 2), D(1, 2)};
    for (int e = 0; e < 6; ++e) soa[e * B + i] = entry[e];
  }
  return soa;
}

TEST(CgKernels, MatchEigenOnEveryLength) {
  for (const int B : {1, 2, 3, 5, 8, 13, 16, 17, 625, 4096}) {
    SCOPED_TRACE(B);
    const std::size_t n = 3 * static_cast<std::size_t>(B);
    const Eigen::Matrix3Xd p = random_field(B, 1), q = random_field(B, 2);
    Eigen::Matrix3Xd x = random_field(B, 3), r = random_field(B, 4);
    const double alpha = 0.37;

    const double pq = simd_dot(p.data(), q.data(), n);
    EXPECT_LE(std::abs(pq - p.cwiseProduct(q).sum()), 1e-12 * p.cwiseProduct(q).cwiseAbs().sum());

    Eigen::Matrix3Xd x_ref = x, r_ref = r;
    x_ref.noalias() += alpha * p;
    r_ref.noalias() -= alpha * q;
    const double rr = simd_update_iterate(x.data(), r.data(), p.data(), q.data(), alpha, n);
    EXPECT_EQ(x, x_ref);
    EXPECT_EQ(r, r_ref);
    EXPECT_LE(std::abs(rr - r_ref.squaredNorm()), 1e-12 * r_ref.squaredNorm());

    std::vector<Eigen::Matrix3d> blocks;
    const std::vector<double> soa = inverse_blocks(B, 5, blocks);
    Eigen::Matrix3Xd z(3, B), z_ref(3, B);
    for (int i = 0; i < B; ++i) z_ref.col(i) = blocks[i] * r.col(i);
    const double rz = simd_jacobi(soa.data(), static_cast<std::size_t>(B), r.data(), z.data());
    EXPECT_LE((z - z_ref).cwiseAbs().maxCoeff(), 1e-14 * z_ref.cwiseAbs().maxCoeff());
    EXPECT_LE(std::abs(rz - r.cwiseProduct(z_ref).sum()), 1e-12 * r.cwiseProduct(z_ref).cwiseAbs().sum());

    Eigen::Matrix3Xd pp = p, pp_ref = z + 0.6 * p;
    simd_xpby(pp.data(), z.data(), 0.6, n);
    EXPECT_EQ(pp, pp_ref);
  }
}

TEST(CgKernels, InvertsSymmetricBlocksAsEigenDoes) {
  for (const int B : {1, 7, 8, 9, 625}) {
    SCOPED_TRACE(B);
    std::vector<Eigen::Matrix3d> blocks;
    inverse_blocks(B, 11, blocks);  // symmetric positive definite blocks
    blocks[0] *= 1e-6;              // and a small one
    std::vector<Eigen::Matrix3d> inverse(B);
    std::vector<double> soa(6 * B);
    simd_invert_blocks(blocks.data()->data(), B, inverse.data()->data(), soa.data());
    for (int i = 0; i < B; ++i) {
      const Eigen::Matrix3d ref = blocks[i].inverse();
      EXPECT_LE((inverse[i] - ref).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff()) << "block " << i;
      EXPECT_EQ(inverse[i], inverse[i].transpose());
      const double entry[6] = {inverse[i](0, 0), inverse[i](1, 1), inverse[i](2, 2),
                               inverse[i](0, 1), inverse[i](0, 2), inverse[i](1, 2)};
      for (int e = 0; e < 6; ++e) EXPECT_EQ(soa[e * B + i], entry[e]);
    }
  }
}

TEST(CgKernels, EveryTargetGivesTheSameBits) {
  const int B = 37;
  const std::size_t n = 3 * B;
  const Eigen::Matrix3Xd p = random_field(B, 6), q = random_field(B, 7), r0 = random_field(B, 8);
  std::vector<Eigen::Matrix3d> blocks;
  const std::vector<double> soa = inverse_blocks(B, 9, blocks);
  struct Bits {
    double pq, rr, rz;
    Eigen::Matrix3Xd x, r, z;
    std::vector<double> inverse;
  };
  const auto run = [&] {
    Bits b{0, 0, 0, Eigen::Matrix3Xd::Zero(3, B), r0, Eigen::Matrix3Xd(3, B), std::vector<double>(15 * B)};
    b.pq = simd_dot(p.data(), q.data(), n);
    b.rr = simd_update_iterate(b.x.data(), b.r.data(), p.data(), q.data(), 0.3, n);
    b.rz = simd_jacobi(soa.data(), B, b.r.data(), b.z.data());
    simd_invert_blocks(blocks.data()->data(), B, b.inverse.data(), b.inverse.data() + 9 * B);
    return b;
  };
  const Bits first = run();
  const std::string targets = testing::for_each_highway_target([&](const char* target) {
    const Bits b = run();
    EXPECT_EQ(std::memcmp(&b.pq, &first.pq, sizeof(double)), 0) << target;
    EXPECT_EQ(std::memcmp(&b.rr, &first.rr, sizeof(double)), 0) << target;
    EXPECT_EQ(std::memcmp(&b.rz, &first.rz, sizeof(double)), 0) << target;
    EXPECT_EQ(std::memcmp(b.z.data(), first.z.data(), sizeof(double) * n), 0) << target;
    EXPECT_EQ(std::memcmp(b.inverse.data(), first.inverse.data(), sizeof(double) * b.inverse.size()), 0)
        << target;
  });
  EXPECT_FALSE(targets.empty());
}

}  // namespace
}  // namespace clothsim
