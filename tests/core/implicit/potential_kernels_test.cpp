// The implicit step's SIMD passes (start lengths, Phi and its gradient, the Newton matrix's
// assembly, the block mat-vec) against their scalar references: the same lengths to the bit,
// the same Phi, gradient, matrix and product to rounding, the same NaNs, the same bits on
// every Highway target this CPU runs, and an implicit run bit-identical from target to target.
#include "core/implicit/potential_kernels.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "test_support.h"
#include "core/implicit/sparse_system.h"
#include "core/implicit/step_potential.h"
#include "core/kernel_test_support.h"
#include "core/run/simulation.h"
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
    "structural: {}, shear: {}",           "structural: {}, bend: {}", "shear: {}, bend: {}"};

// An nx x ny sheet with the given spring types (parameters differing per type), air drag, a
// pinned corner and a free ball, so the arrays have an immovable body and one past the
// particles that no spring touches.
Model sheet(int nx, int ny, const std::string& types) {
  const std::string springs = typed_springs(types);
  return model_from_yaml("gravity: [0, -9.8, 0]\nair_drag: 0.2\ncloth: {particles: [" +
                         std::to_string(nx) + ", " + std::to_string(ny) +
                         "], size: [2, 1.5], particle_mass: 0.05, pinned: [[0, 0]], springs: {" +
                         springs + "}}\nspheres: [{center: [0, -2, 0], radius: 0.5, kinematic: false, mass: 2}]\n");
}

// A start state near the grid (every spring stretched or compressed a little), random
// velocities and a random dv (seeded), and the start lengths by slot.
struct StepCase {
  Model model;
  State start;
  Eigen::Matrix3Xd dv;
  std::vector<double> length;
};

StepCase step_case(Model m, unsigned seed) {
  StepCase s{std::move(m), {}, {}, {}};
  s.start = initial_state(s.model);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int B = s.model.num_bodies();
  s.dv.resize(3, B);
  for (int b = 0; b < B; ++b)
    for (int c = 0; c < 3; ++c) {
      s.start.x(c, b) += 0.02 * u(rng);
      s.start.v(c, b) = u(rng);
      s.dv(c, b) = 0.1 * u(rng);
    }
  for (int b = 0; b < B; ++b)
    if (s.start.inv_mass[b] == 0.0) s.start.v.col(b).setZero(), s.dv.col(b).setZero();
  step_lengths(s.model, s.start.x, s.length);
  return s;
}

constexpr double kH = 1e-3;

// Each spring's length by slot is the scalar loop's to the bit, and so is the strain.
void expect_same_lengths(const Model& m, const Eigen::Matrix3Xd& x) {
  std::vector<double> by_slot, by_spring;
  const double strain = step_lengths(m, x, by_slot);
  const double reference = spring_lengths(m.springs, x, by_spring);
  if (std::isnan(reference)) {
    EXPECT_TRUE(std::isnan(strain));
  } else {
    EXPECT_EQ(strain, reference);
  }
  ASSERT_EQ(by_slot.size(), slot_count(m.spring_layout, m.springs.size()));
  for (std::size_t s = 0; s < m.springs.size(); ++s) {
    const double a = by_slot[m.spring_layout.covers(m.springs.size()) ? m.spring_layout.slot[s] : s];
    EXPECT_TRUE(a == by_spring[s] || (std::isnan(a) && std::isnan(by_spring[s]))) << "spring " << s;
  }
}

// The largest spring term h |T| of Phi's gradient at the end of the step: what "relative per
// spring force" is relative to.
double largest_spring_push(const StepCase& s, const Eigen::Matrix3Xd& y) {
  const Springs& sp = s.model.springs;
  std::vector<double> ln;
  spring_lengths(sp, s.start.x, ln);
  double out = 0.0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    const double l = (y.col(sp.a[i]) - y.col(sp.b[i])).norm();
    out = std::max(out, kH * std::abs(step_spring_tension(l, sp.rest[i], ln[i], sp.ks[i], sp.kd[i], kH)));
  }
  return out;
}

void expect_same_potential(const StepCase& s) {
  Eigen::Matrix3Xd y, g, y_ref, g_ref;
  const PotentialValue a = step_potential(s.model, s.start, kH, s.length, s.dv, y, g);
  const PotentialValue b = step_potential_scalar(s.model, s.start, kH, s.length, s.dv, y_ref, g_ref);
  EXPECT_EQ(y, y_ref);
  EXPECT_LE(std::abs(a.phi - b.phi), 1e-12 * b.magnitude) << a.phi << " vs " << b.phi;
  EXPECT_LE(std::abs(a.magnitude - b.magnitude), 1e-12 * b.magnitude);
  const double scale = largest_spring_push(s, y);
  EXPECT_LE((g - g_ref).cwiseAbs().maxCoeff(), 1e-12 * scale) << "largest spring term " << scale;
  EXPECT_EQ(g.col(s.model.num_bodies() - 1), g_ref.col(s.model.num_bodies() - 1));  // the ball: no spring
}

// The exact Newton matrix at the setup's end-of-step positions (compressed springs included).
SpringBlockMatrix newton_matrix(const StepCase& s) {
  SpringBlockMatrix A;
  build_pattern(s.model, A);
  const Eigen::Matrix3Xd y = s.start.x + kH * (s.start.v + s.dv);
  assemble_step_hessian(s.model, s.start.inv_mass, kH, s.length, y, HessianBlocks::Exact, A);
  return A;
}

// Per entry, within `tolerance` (1e-12: the same numbers) of (|A| |p|)_i: the sum of the
// absolute values of the terms the entry adds up (a relative error per entry that stays
// meaningful where the terms cancel).
void expect_same_product(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, double tolerance = 1e-12) {
  Eigen::Matrix3Xd out, ref, bound;
  multiply(A, p, out);
  multiply_scalar(A, p, ref);
  SpringBlockMatrix abs = A;
  for (Mat3& D : abs.diag) D = D.cwiseAbs();
  for (auto* v : {&abs.ux, &abs.uy, &abs.uz, &abs.alpha, &abs.beta})
    for (double& x : *v) x = std::abs(x);
  multiply_scalar(abs, p.cwiseAbs(), bound);
  EXPECT_TRUE(((out - ref).cwiseAbs().array() <= tolerance * bound.array()).all())
      << "worst " << ((out - ref).cwiseAbs().array() / bound.array().max(1e-300)).maxCoeff();
}

// The SIMD assembly against the scalar reference, exact or projected, with inverse masses w:
// per spring, u within 1e-12 (where an end moves: the reference leaves u as it was where
// neither does) and (alpha, beta) within 1e-12 of h^2 (axial + |T / l|), the size of the
// block's terms; per body, the diagonal blocks (both) within 1e-12 of the sum of the sizes
// of the terms they add up.
void expect_same_matrix(const StepCase& s, const Eigen::VectorXd& w, bool project) {
  SCOPED_TRACE(project ? "projected" : "exact");
  const Model& m = s.model;
  const Eigen::Matrix3Xd y = s.start.x + kH * (s.start.v + s.dv);
  SpringBlockMatrix A, ref;
  build_pattern(m, A);
  build_pattern(m, ref);
  assemble_step_hessian(m, w, kH, s.length, y, project ? HessianBlocks::Projected : HessianBlocks::Exact, A);
  assemble_step_hessian_scalar(m, w, kH, s.length, y, project ? HessianBlocks::Projected : HessianBlocks::Exact, ref);
  const double h2 = kH * kH;
  const Springs& sp = m.springs;
  std::vector<double> bound(m.num_bodies(), 0.0);
  for (int i = 0; i < m.num_bodies(); ++i)
    bound[i] = w[i] == 0.0 ? 0.0 : 1.0 / w[i] + kH * (i < m.num_particles ? m.air_drag : 0.0);
  for (std::size_t i = 0; i < sp.size(); ++i) {
    const std::size_t k = A.slot[i];
    ASSERT_EQ(k, static_cast<std::size_t>(ref.slot[i]));
    const StepSpringBlock block = step_spring_block(y.col(sp.a[i]) - y.col(sp.b[i]), sp.rest[i],
                                                    s.length[k], sp.ks[i], sp.kd[i], kH);
    const double size = h2 * (block.axial + std::abs(block.transverse));
    bound[sp.a[i]] += size;
    bound[sp.b[i]] += size;
    if (w[sp.a[i]] != 0.0 || w[sp.b[i]] != 0.0) {
      EXPECT_LE((A.u(i) - ref.u(i)).cwiseAbs().maxCoeff(), 1e-12) << "spring " << i;
    }
    for (const auto& [x, x_ref] : {std::pair{A.alpha[k], ref.alpha[k]}, std::pair{A.beta[k], ref.beta[k]},
                                   std::pair{A.alpha_projected[k], ref.alpha_projected[k]},
                                   std::pair{A.beta_projected[k], ref.beta_projected[k]}})
      EXPECT_LE(std::abs(x - x_ref), 1e-12 * size) << "spring " << i << ": " << x << " vs " << x_ref;
  }
  for (int i = 0; i < m.num_bodies(); ++i) {
    EXPECT_LE((A.diag[i] - ref.diag[i]).cwiseAbs().maxCoeff(), 1e-12 * bound[i]) << "body " << i;
    EXPECT_LE((A.diag_projected[i] - ref.diag_projected[i]).cwiseAbs().maxCoeff(), 1e-12 * bound[i])
        << "body " << i;
    EXPECT_EQ(A.diag[i], A.diag[i].transpose()) << "body " << i;
    if (w[i] == 0.0) {
      EXPECT_TRUE(A.diag[i].isIdentity(0.0) && A.diag_projected[i].isIdentity(0.0)) << "body " << i;
    }
  }
  // Every slot without a spring (padding, gaps) holds zeros: the mat-vec reads them.
  std::vector<char> used(A.alpha.size(), 0);
  for (std::size_t i = 0; i < sp.size(); ++i) used[A.slot[i]] = 1;
  for (std::size_t k = 0; k < used.size(); ++k) {
    if (used[k]) continue;
    for (const auto* v : {&A.ux, &A.uy, &A.uz, &A.alpha, &A.beta, &A.alpha_projected, &A.beta_projected})
      ASSERT_EQ((*v)[k], 0.0) << "slot " << k;
  }
}

// Both kinds of matrix, with the sheet's own inverse masses and with a pinned pair (a spring
// neither of whose ends moves) and a pinned particle in the middle of the sheet.
void expect_same_matrices(const StepCase& s) {
  expect_same_matrix(s, s.start.inv_mass, false);
  expect_same_matrix(s, s.start.inv_mass, true);
  Eigen::VectorXd w = s.start.inv_mass;
  if (s.model.num_particles < 2) return;
  w[1] = 0.0;
  w[s.model.num_particles / 2] = 0.0;
  expect_same_matrix(s, w, false);
}

Eigen::Matrix3Xd random_vector(int B, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd p(3, B);
  for (int b = 0; b < B; ++b)
    for (int c = 0; c < 3; ++c) p(c, b) = u(rng);
  return p;
}

TEST(PotentialKernels, EveryPassMatchesItsScalarReferenceOnEverySheetAndSpringSet) {
  const std::vector<std::pair<int, int>> sizes{{25, 25}, {64, 64}, {7, 5}, {1, 9}, {9, 1},
                                               {2, 2},   {3, 3},   {2, 17}, {50, 3}};
  unsigned seed = 1;
  for (const auto& [nx, ny] : sizes)
    for (const std::string& types : kTypeSets) {
      SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny) + " {" + types + "}");
      const StepCase s = step_case(sheet(nx, ny, types), seed++);
      ASSERT_TRUE(s.model.spring_layout.covers(s.model.springs.size()) || s.model.springs.size() == 0);
      expect_same_lengths(s.model, s.start.x);
      expect_same_potential(s);
      expect_same_matrices(s);
      expect_same_product(newton_matrix(s), random_vector(s.model.num_bodies(), seed++));
    }
}

// The float copy's product (SpringBlockMatrix::single, on with ImplicitDef::single_from at 0)
// against the double scalar reference: per entry within 1e-6 of (|A| |p|)_i, float's rounding
// of the numbers (2^-24 each) through a few products.
void expect_single_product(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p) {
  ASSERT_NE(A.refresh_single_copy, nullptr);
  expect_same_product(A, p, 1e-6);
}

TEST(PotentialKernels, TheFloatCopysProductIsTheDoubleOneToFloatRounding) {
  unsigned seed = 100;
  for (const auto& [nx, ny] : std::vector<std::pair<int, int>>{{25, 25}, {7, 5}, {1, 9}, {2, 2}, {50, 3}})
    for (const std::string& types : kTypeSets) {
      SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny) + " {" + types + "}");
      Model m = sheet(nx, ny, types);
      m.implicit.single_from = 0;
      const StepCase s = step_case(std::move(m), seed++);
      if (s.model.springs.size() == 0) continue;  // (1 x 9 shear, 2 x 2 bend) no families: scalar
      SpringBlockMatrix A = newton_matrix(s);  // exact: compressed springs, a pinned corner
      expect_single_product(A, random_vector(s.model.num_bodies(), seed++));
      A.use_projected();  // the copy follows the matrix it is made from
      expect_single_product(A, random_vector(s.model.num_bodies(), seed++));
      // A diagonal changed after the assembly (contact terms do) reaches it through refresh_copies.
      A.diag[s.model.num_particles / 2] += Mat3::Identity() * 3.0;
      A.refresh_copies();
      expect_single_product(A, random_vector(s.model.num_bodies(), seed++));
      // and through the refresh of R alone (the barrier's terms change only D)
      A.diag[s.model.num_particles / 3] += Mat3::Identity() * 5.0;
      A.refresh_copies(SpringBlockMatrix::Refresh::Rest);
      expect_single_product(A, random_vector(s.model.num_bodies(), seed++));
    }
}

TEST(PotentialKernels, TheFloatCopyKeepsAStiffSheetsEnergyAndRigidMotions) {
  // k = 1e7 N/m, 1 g particles, h = 1/30 s: the springs' terms are over 1e6 times the mass's
  // on the diagonal, so float's rounding of D alone (2^-24 of it) would be the size of the mass
  // term. Applied to the difference of a spring's ends, the rounding scales each spring's own
  // energy by 1 +- a few 2^-24, and a translation sees the mass term alone, as in double.
  Model m = model_from_yaml(
      "cloth: {particles: [20, 20], size: [1, 1], particle_mass: 0.001, pinned: [[0, 0]], springs: "
      "{structural: {stiffness: 1e7, damping: 10}, shear: {stiffness: 1e7, damping: 10}, bend: {stiffness: 1e7}}}\n");
  m.implicit.single_from = 0;
  const StepCase s = step_case(std::move(m), 7);
  const double h = 1.0 / 30;
  SpringBlockMatrix A;
  build_pattern(s.model, A);
  const Eigen::Matrix3Xd y = s.start.x + h * (s.start.v + s.dv);
  assemble_step_hessian(s.model, s.start.inv_mass, h, s.length, y, HessianBlocks::Projected, A);
  const int B = s.model.num_bodies();
  ASSERT_GT(A.diag[B / 2](0, 0), 1e6 * 0.001);  // the springs' terms over a million times the mass's
  Eigen::Matrix3Xd out, ref;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Eigen::Matrix3Xd p = random_vector(B, seed);
    multiply(A, p, out);
    multiply_scalar(A, p, ref);
    const double energy = p.cwiseProduct(ref).sum();
    EXPECT_LE(std::abs(p.cwiseProduct(out).sum() - energy), 1e-6 * energy) << "seed " << seed;
  }
  Eigen::Matrix3Xd c(3, B);  // a translation of the free particles
  for (int i = 0; i < B; ++i) c.col(i) = s.start.inv_mass[i] == 0.0 ? Vec3::Zero() : Vec3(0.3, -1.0, 0.7);
  multiply(A, c, out);
  multiply_scalar(A, c, ref);
  // Away from the pin, A c is the mass term 1e-3 c (and drag): within 1e-6 of it in float.
  for (int i = 0; i < B; ++i) {
    if (s.start.inv_mass[i] == 0.0 || i <= 2 * 20 + 2) continue;  // the pin's springs reach 2 rows
    EXPECT_LE((out.col(i) - ref.col(i)).norm(), 1e-6 * ref.col(i).norm()) << "particle " << i;
  }
}

TEST(PotentialKernels, PhisEndLengthsAreTheLengthsAtYBitForBit) {
  // implicit_euler starts a step from the lengths the last step's final Phi left at its end
  // positions: they must be step_lengths' own, and so must their strain.
  for (const auto& [nx, ny] : std::vector<std::pair<int, int>>{{25, 25}, {7, 5}, {1, 9}, {64, 3}}) {
    SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny));
    StepCase s = step_case(sheet(nx, ny, "structural: {}, shear: {}, bend: {}"), 21);
    s.dv(0, nx * ny - 1) = 30.0;  // a stretched spring at the last particle: the strain is its
    Eigen::Matrix3Xd y, g;
    std::vector<double> end, at_y;
    step_potential(s.model, s.start, kH, s.length, s.dv, y, g, &end);
    const double strain = step_lengths(s.model, y, at_y);
    ASSERT_EQ(end.size(), at_y.size());
    for (std::size_t i = 0; i < s.model.springs.size(); ++i) {
      const std::size_t k = s.model.spring_layout.slot[i];
      EXPECT_EQ(std::memcmp(&end[k], &at_y[k], sizeof(double)), 0) << "spring " << i;
    }
    EXPECT_EQ(step_strain(s.model, end), strain);
    EXPECT_GT(strain, 0.0);
  }
}

TEST(PotentialKernels, SpringsOutsideTheFamiliesAndAStaleLayoutRunTheScalarPath) {
  Model m = sheet(6, 5, "structural: {}, shear: {}");
  add_spring_outside_the_families(m);
  ASSERT_EQ(m.spring_layout.others.size(), 1u);
  StepCase s = step_case(m, 7);
  s.start.x.col(29) += Vec3(5.0, 0.0, 0.0);  // the long spring is the most stretched: its strain wins
  step_lengths(s.model, s.start.x, s.length);
  expect_same_lengths(s.model, s.start.x);
  EXPECT_GT(step_lengths(s.model, s.start.x, s.length), 5.0);
  expect_same_potential(s);
  expect_same_matrices(s);
  expect_same_product(newton_matrix(s), random_vector(s.model.num_bodies(), 8));
  {  // with springs outside the families, Phi leaves no end lengths (the step recomputes them)
    Eigen::Matrix3Xd y, g;
    std::vector<double> end(3, 1.0);
    step_potential(s.model, s.start, kH, s.length, s.dv, y, g, &end);
    EXPECT_TRUE(end.empty());
  }

  m.springs.a.pop_back();  // springs changed after the layout was built: spring order, scalar
  m.springs.b.pop_back();
  m.springs.rest.pop_back();
  m.springs.ks.pop_back();
  m.springs.kd.pop_back();
  m.springs.type.pop_back();
  const StepCase stale = step_case(m, 9);
  EXPECT_EQ(stale.length.size(), m.springs.size());
  Eigen::Matrix3Xd y, g, y_ref, g_ref;
  const PotentialValue a = step_potential(stale.model, stale.start, kH, stale.length, stale.dv, y, g);
  const PotentialValue b = step_potential_scalar(stale.model, stale.start, kH, stale.length, stale.dv, y_ref, g_ref);
  EXPECT_EQ(a.phi, b.phi);  // the same loop: the same bits
  EXPECT_EQ(g, g_ref);
  const SpringBlockMatrix A = newton_matrix(stale);
  EXPECT_EQ(A.layout, nullptr);
  Eigen::Matrix3Xd out, ref;
  multiply(A, random_vector(m.num_bodies(), 10), out);
  multiply_scalar(A, random_vector(m.num_bodies(), 10), ref);
  EXPECT_EQ(out, ref);
}

TEST(PotentialKernels, NaNPropagatesAsInTheScalarPasses) {
  StepCase s = step_case(sheet(7, 5, "structural: {}, shear: {}, bend: {}"), 11);
  const auto nan_pattern = [](const Eigen::Matrix3Xd& a) { return a.array().isNaN().eval(); };
  for (const int particle : {16, 34}) {  // interior, and the last particle (every family's end)
    StepCase bad = s;
    bad.dv(1, particle) = std::nan("");
    Eigen::Matrix3Xd y, g, y_ref, g_ref;
    const PotentialValue a = step_potential(bad.model, bad.start, kH, bad.length, bad.dv, y, g);
    const PotentialValue b = step_potential_scalar(bad.model, bad.start, kH, bad.length, bad.dv, y_ref, g_ref);
    EXPECT_TRUE(std::isnan(a.phi) && std::isnan(b.phi));
    EXPECT_TRUE((nan_pattern(g) == nan_pattern(g_ref)).all()) << "particle " << particle;
    bad.start.x(0, particle) = std::nan("");
    expect_same_lengths(bad.model, bad.start.x);
    std::vector<double> length;
    EXPECT_TRUE(std::isnan(step_lengths(bad.model, bad.start.x, length)));

    {  // the assembly at end positions with a NaN: the same NaN blocks as the reference
      const Eigen::Matrix3Xd y_bad = bad.start.x + kH * (bad.start.v + bad.dv);
      SpringBlockMatrix A, ref;
      build_pattern(bad.model, A);
      build_pattern(bad.model, ref);
      assemble_step_hessian(bad.model, bad.start.inv_mass, kH, s.length, y_bad, HessianBlocks::Exact, A);
      assemble_step_hessian_scalar(bad.model, bad.start.inv_mass, kH, s.length, y_bad, HessianBlocks::Exact, ref);
      for (int body = 0; body < bad.model.num_bodies(); ++body) {
        EXPECT_EQ(A.diag[body].array().isNaN().any(), ref.diag[body].array().isNaN().any()) << "body " << body;
        EXPECT_EQ(A.diag_projected[body].array().isNaN().any(), ref.diag_projected[body].array().isNaN().any())
            << "body " << body;
      }
      for (std::size_t k = 0; k < A.alpha.size(); ++k)
        EXPECT_EQ(std::isnan(A.alpha[k]), std::isnan(ref.alpha[k])) << "slot " << k;
    }
    const SpringBlockMatrix A = newton_matrix(s);
    Eigen::Matrix3Xd p = random_vector(s.model.num_bodies(), 12), out, ref;
    p(2, particle) = std::nan("");
    multiply(A, p, out);
    multiply_scalar(A, p, ref);
    EXPECT_TRUE((nan_pattern(out) == nan_pattern(ref)).all()) << "particle " << particle;
  }
}

TEST(PotentialKernels, CoincidentEndsGiveNoGradientAsInTheScalarPass) {
  StepCase s = step_case(sheet(6, 4, "structural: {}, shear: {}, bend: {}"), 5);
  s.start.v.setZero();
  s.dv.setZero();
  s.start.x.col(8) = s.start.x.col(9);  // a structural spring of length 0 at the end of the step
  s.start.x.col(15) = s.start.x.col(8);  // and a shear one
  step_lengths(s.model, s.start.x, s.length);
  Eigen::Matrix3Xd y, g;
  step_potential(s.model, s.start, kH, s.length, s.dv, y, g);
  EXPECT_TRUE(g.allFinite());
  expect_same_potential(s);
  expect_same_matrices(s);  // an isotropic block where a spring has no direction
}

TEST(PotentialKernels, EveryTargetGivesTheSameBits) {
  // No fused multiply-add, no mixing of lanes and Phi summed in 16 fixed partial sums:
  // SCALAR .. AVX3 compute the same numbers.
  const StepCase s = step_case(sheet(37, 23, "structural: {}, shear: {}, bend: {}"), 13);
  const SpringBlockMatrix A = newton_matrix(s);
  const Eigen::Matrix3Xd p = random_vector(s.model.num_bodies(), 14);
  Model single_model = s.model;  // and the float copy's refresh and product (block_matrix.h)
  single_model.implicit.single_from = 0;
  struct Bits {
    std::vector<double> length;
    double strain, phi, magnitude;
    Eigen::Matrix3Xd gradient, product, single_product;
    SpringBlockMatrix matrix, single;
  };
  const Eigen::Matrix3Xd y_end = s.start.x + kH * (s.start.v + s.dv);
  const auto run = [&] {
    Bits b;
    build_pattern(s.model, b.matrix);
    assemble_step_hessian(s.model, s.start.inv_mass, kH, s.length, y_end, HessianBlocks::Exact, b.matrix);
    b.strain = step_lengths(s.model, s.start.x, b.length);
    Eigen::Matrix3Xd y;
    const PotentialValue v = step_potential(s.model, s.start, kH, s.length, s.dv, y, b.gradient);
    b.phi = v.phi;
    b.magnitude = v.magnitude;
    multiply(A, p, b.product);
    build_pattern(single_model, b.single);
    assemble_step_hessian(single_model, s.start.inv_mass, kH, s.length, y_end, HessianBlocks::Exact, b.single);
    multiply(b.single, p, b.single_product);
    return b;
  };
  const auto same = [](const auto& a, const auto& b, std::size_t n) {
    return std::memcmp(a, b, sizeof(double) * n) == 0;
  };
  const Bits first = run();
  const std::string names = for_each_highway_target([&](const char* name) {
    const Bits b = run();
    EXPECT_TRUE(same(b.length.data(), first.length.data(), b.length.size())) << name;
    EXPECT_TRUE(same(&b.strain, &first.strain, 1)) << name;
    EXPECT_TRUE(same(&b.phi, &first.phi, 1)) << name;
    EXPECT_TRUE(same(&b.magnitude, &first.magnitude, 1)) << name;
    EXPECT_TRUE(same(b.gradient.data(), first.gradient.data(), b.gradient.size())) << name;
    EXPECT_TRUE(same(b.product.data(), first.product.data(), b.product.size())) << name;
    EXPECT_TRUE(same(b.single_product.data(), first.single_product.data(), b.product.size())) << name;
    const SpringBlockMatrix::Single &f = b.single.single, &f0 = first.single.single;
    for (const auto& [v, v0] : {std::pair{&f.ux, &f0.ux}, {&f.alpha, &f0.alpha}, {&f.rest_soa, &f0.rest_soa}})
      EXPECT_EQ(std::memcmp(v->data(), v0->data(), sizeof(float) * v->size()), 0) << name;
    const SpringBlockMatrix& H = b.matrix;
    const SpringBlockMatrix& H0 = first.matrix;
    for (const auto& [v, v0] : {std::pair{&H.ux, &H0.ux}, std::pair{&H.uy, &H0.uy}, std::pair{&H.uz, &H0.uz},
                                std::pair{&H.alpha, &H0.alpha}, std::pair{&H.beta, &H0.beta},
                                std::pair{&H.alpha_projected, &H0.alpha_projected},
                                std::pair{&H.beta_projected, &H0.beta_projected}})
      EXPECT_TRUE(same(v->data(), v0->data(), v->size())) << name;
    EXPECT_TRUE(same(H.diag.data()->data(), H0.diag.data()->data(), 9 * H.diag.size())) << name;
    EXPECT_TRUE(same(H.diag_projected.data()->data(), H0.diag_projected.data()->data(), 9 * H.diag.size()))
        << name;
  });
  ASSERT_FALSE(names.empty());
  std::printf("potential kernel targets compared: %s(default %s)\n", names.c_str(),
              potential_kernel_target());
}

// 40 implicit steps of the drape at its 1e-4 s (Newton, CG, matrix reuse, contacts).
std::vector<double> implicit_drape() {
  const Model m = build_model(load_scene(scene_path("drape.yaml")));
  clothsim::Run run(m, IntegratorKind::ImplicitEuler, 1e-4);
  EXPECT_TRUE(run.advance_to(40 * 1e-4));
  std::vector<double> out(run.state().x.data(), run.state().x.data() + run.state().x.size());
  out.insert(out.end(), run.state().v.data(), run.state().v.data() + run.state().v.size());
  return out;
}

TEST(PotentialKernels, AnImplicitRunIsBitIdenticalFromTargetToTarget) {
  const std::vector<double> a = implicit_drape();
  EXPECT_EQ(std::memcmp(a.data(), implicit_drape().data(), sizeof(double) * a.size()), 0);
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    const std::vector<double> b = implicit_drape();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0) << potential_kernel_target();
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace clothsim
