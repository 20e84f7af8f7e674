// The SIMD spring force pass against the scalar reference: the same forces to rounding, the
// same strain to the bit, the same NaNs; the same bits on every Highway target this CPU runs;
// a run bit-identical from run to run.
#include "core/springs/spring_kernels.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "test_support.h"
#include "core/model/forces.h"
#include "core/kernel_test_support.h"
#include "core/run/simulation.h"
#include "core/springs/spring_force.h"
#include "core/model/state.h"
#include "scene/build_model.h"

namespace clothsim {
namespace {

using testing::model_from_yaml;
using testing::scene_path;
using testing::add_spring_outside_the_families;
using testing::for_each_highway_target;
using testing::typed_springs;

const std::vector<std::string> kTypeSets{
    "structural: {}, shear: {}, bend: {}", "structural: {}", "shear: {}", "bend: {}",
    "structural: {}, shear: {}",           "structural: {}, bend: {}", "shear: {}, bend: {}", ""};

// An nx x ny sheet with the given spring types (stiffness and damping differing per type) and a
// ball, so the force array has a body past the particles the kernel must leave alone.
Model sheet(int nx, int ny, const std::string& types) {
  const std::string springs = typed_springs(types);
  return model_from_yaml("cloth: {particles: [" + std::to_string(nx) + ", " + std::to_string(ny) +
                         "], size: [2, 1.5], springs: {" + springs +
                         "}}\nspheres: [{center: [0, -2, 0], radius: 0.5}]\n");
}

// A state near the grid with every spring stretched or compressed a little, and random
// velocities (seeded: the same numbers every run).
void perturb(const Model& m, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  x = m.initial_x;
  v.resize(3, m.num_bodies());
  for (int b = 0; b < m.num_bodies(); ++b)
    for (int c = 0; c < 3; ++c) {
      x(c, b) += 0.02 * u(rng);
      v(c, b) = u(rng);
    }
}

struct Pass {
  Eigen::Matrix3Xd f;
  double strain;
};

Pass simd(const Model& m, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  Pass p{Eigen::Matrix3Xd::Zero(3, m.num_bodies()), 0.0};
  p.strain = accumulate_spring_forces(m, x, v, p.f);
  return p;
}

Pass scalar(const Model& m, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  Pass p{Eigen::Matrix3Xd::Zero(3, m.num_bodies()), 0.0};
  p.strain = accumulate_spring_forces_scalar(m.springs, x, v, p.f);
  return p;
}

// The largest spring force |f_a| of the state: what "relative per force" is relative to.
double largest_spring_force(const Model& m, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  const Springs& s = m.springs;
  double out = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    out = std::max(out, spring_damper_force(x.col(s.a[i]), x.col(s.b[i]), v.col(s.a[i]), v.col(s.b[i]),
                                            s.rest[i], s.ks[i], s.kd[i]).norm());
  return out;
}

void expect_same_as_scalar(const Model& m, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  const Pass a = simd(m, x, v), b = scalar(m, x, v);
  EXPECT_EQ(a.strain, b.strain);  // the exact maximum of the rounded l / l0, both ways
  const double scale = largest_spring_force(m, x, v);
  const double worst = (a.f - b.f).cwiseAbs().maxCoeff();
  EXPECT_LE(worst, 1e-12 * scale) << "largest spring force " << scale;
  EXPECT_EQ(a.f.col(m.num_bodies() - 1).norm(), 0.0);  // the ball: no spring
}

TEST(SpringKernels, ForcesMatchTheScalarPassOnEverySheetAndSpringSet) {
  const std::vector<std::pair<int, int>> sizes{{25, 25}, {64, 64}, {7, 5}, {1, 9}, {9, 1},
                                               {2, 2},   {3, 3},   {2, 17}, {1, 1}};
  unsigned seed = 1;
  for (const auto& [nx, ny] : sizes)
    for (const std::string& types : kTypeSets) {
      SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny) + " {" + types + "}");
      const Model m = sheet(nx, ny, types);
      Eigen::Matrix3Xd x, v;
      perturb(m, x, v, seed++);
      expect_same_as_scalar(m, x, v);
    }
}

TEST(SpringKernels, SpringsOutsideTheFamiliesRunInTheScalarPass) {
  Model m = sheet(6, 5, "structural: {}, shear: {}");
  add_spring_outside_the_families(m);
  ASSERT_EQ(m.spring_layout.others.size(), 1u);
  Eigen::Matrix3Xd x, v;
  perturb(m, x, v, 7);
  x.col(29) += Vec3(5.0, 0.0, 0.0);  // the long spring is the most stretched: its strain wins
  expect_same_as_scalar(m, x, v);
  EXPECT_GT(simd(m, x, v).strain, 5.0);
}

TEST(SpringKernels, AModelWhoseLayoutIsStaleRunsTheScalarPass) {
  Model m = sheet(5, 5, "structural: {}");
  m.springs.a.pop_back();  // springs changed after the layout was built
  m.springs.b.pop_back();
  m.springs.rest.pop_back();
  m.springs.ks.pop_back();
  m.springs.kd.pop_back();
  m.springs.type.pop_back();
  Eigen::Matrix3Xd x, v;
  perturb(m, x, v, 3);
  const Pass a = simd(m, x, v), b = scalar(m, x, v);
  EXPECT_EQ(a.strain, b.strain);
  EXPECT_EQ(a.f, b.f);  // the same loop: the same bits
}

TEST(SpringKernels, NaNPropagatesAsInTheScalarPass) {
  const Model m = sheet(7, 5, "structural: {}, shear: {}, bend: {}");
  Eigen::Matrix3Xd x, v;
  perturb(m, x, v, 11);
  const auto same_nans = [&](const Eigen::Matrix3Xd& xs, const Eigen::Matrix3Xd& vs) {
    const Pass a = simd(m, xs, vs), b = scalar(m, xs, vs);
    EXPECT_EQ(std::isnan(a.strain), std::isnan(b.strain));
    if (!std::isnan(b.strain)) {
      EXPECT_EQ(a.strain, b.strain);
    }
    EXPECT_TRUE((a.f.array().isNaN() == b.f.array().isNaN()).all());
    return std::isnan(a.strain);
  };
  Eigen::Matrix3Xd xn = x;
  xn(1, 16) = std::nan("");  // an interior particle: NaN length on all its springs
  EXPECT_TRUE(same_nans(xn, v));
  xn = x;
  xn(0, 34) = std::nan("");  // the last particle, at the end of every family's range
  EXPECT_TRUE(same_nans(xn, v));
  Eigen::Matrix3Xd vn = v;
  vn(2, 0) = std::nan("");  // a NaN velocity: NaN forces, lengths (and strain) fine
  EXPECT_FALSE(same_nans(x, vn));
}

TEST(SpringKernels, CoincidentEndsGiveNoForceAsInTheScalarPass) {
  const Model m = sheet(6, 4, "structural: {}, shear: {}, bend: {}");
  Eigen::Matrix3Xd x, v;
  perturb(m, x, v, 5);
  x.col(8) = x.col(9);  // a structural spring of length 0
  x.col(15) = x.col(8);  // and a shear one
  const Pass a = simd(m, x, v);
  EXPECT_TRUE(a.f.allFinite());
  expect_same_as_scalar(m, x, v);
}

TEST(SpringKernels, EveryTargetGivesTheSameBits) {
  // No fused multiply-add and no mixing of lanes: SCALAR .. AVX3 compute the same numbers.
  const Model m = sheet(37, 23, "structural: {}, shear: {}, bend: {}");
  Eigen::Matrix3Xd x, v;
  perturb(m, x, v, 13);
  const Pass first = simd(m, x, v);
  const std::string all = for_each_highway_target([&](const char* target) {
    const Pass p = simd(m, x, v);
    EXPECT_EQ(std::memcmp(p.f.data(), first.f.data(), sizeof(double) * p.f.size()), 0) << target;
    EXPECT_EQ(p.strain, first.strain) << target;
  });
  ASSERT_FALSE(all.empty());
  RecordProperty("targets", all);
  std::printf("spring kernel targets compared: %s(default %s)\n", all.c_str(), spring_kernel_target());
}

std::vector<double> drape_after_200_steps() {
  const Model m = build_model(load_scene(scene_path("drape.yaml")));
  clothsim::Run run(m, IntegratorKind::SymplecticEuler, m.dt);
  EXPECT_TRUE(run.advance_to(200 * m.dt));
  EXPECT_EQ(run.state().step, 200);
  std::vector<double> out(run.state().x.data(), run.state().x.data() + run.state().x.size());
  out.insert(out.end(), run.state().v.data(), run.state().v.data() + run.state().v.size());
  return out;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(SpringKernels, ARunIsBitIdenticalFromRunToRunThreadToThreadAndTargetToTarget) {
  const std::vector<double> a = drape_after_200_steps();
  EXPECT_TRUE(same_bits(a, drape_after_200_steps()));
  std::vector<double> c;
  std::thread([&] { c = drape_after_200_steps(); }).join();  // another thread's scratch
  EXPECT_TRUE(same_bits(a, c));
  for_each_highway_target([&](const char* target) { EXPECT_TRUE(same_bits(a, drape_after_200_steps())) << target; });
}

}  // namespace
}  // namespace clothsim
