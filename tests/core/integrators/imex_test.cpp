// imex (integrators/imex.cpp) against its theory: order 1 on the damped spring and 2 undamped
// (velocity Verlet); on u'' + c u' + w^2 u = 0 its step, read off the code, is the closed form
// (det d^2, trace 1 + d^2 - d (1 + d) (w h)^2 / 2, d = 1 / (1 + ch/2)), stable for w h < 2
// whatever the damping, where symplectic Euler's and Verlet's limits shrink with it; energy
// never gained with the dampers; one force pass a step, carried only while the state is the
// one the last step left.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "test_support.h"
#include "core/integrators/oscillator.h"
#include "core/integrators/verlet.h"
#include "core/integrators/whole_state.h"
#include "core/model/stiffness_estimate.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kImex = IntegratorKind::Imex;

std::string damping(double c) {
  std::ostringstream s;
  s << "cloth.springs.structural.damping=" << c;
  return s.str();
}

// Orders from |r| h = 0.05 down three halvings, printed.
std::vector<double> orders_on(const SceneDef& scene, const char* what) {
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
  const std::vector<double> p = observed_orders(scene, kImex, h0, T);
  std::printf("imex orders on the %s spring (zeta %.2f): %.3f %.3f %.3f\n", what, o.zeta(), p[0], p[1], p[2]);
  return p;
}

TEST(Imex, ConvergesAtFirstOrderOnTheDampedSpring) {
  // The two backward-Euler half kicks of the damping err by (ch)^2 / 4 a step (imex.cpp); at
  // zeta = 0.5 that term dominates the elastic part's h^2 from the first step size on.
  for (double p : orders_on(load_spring_scene({damping(10.0)}), "damped")) EXPECT_NEAR(p, 1.0, 0.1);
}

TEST(Imex, ConvergesAtSecondOrderUndampedWhereItIsVelocityVerlet) {
  const SceneDef scene = load_spring_scene({damping(0.0)});
  for (double p : orders_on(scene, "undamped")) EXPECT_NEAR(p, 2.0, 0.05);
  const Oscillator o = oscillator_of(scene);
  const double h = 1.0 / std::round(o.fastest_rate() / 0.05);
  EXPECT_NEAR(error_at(scene, kImex, h, 1.0), error_at(scene, IntegratorKind::VelocityVerlet, h, 1.0), 1e-12);
}

// The damped spring with extension e and rate u along its axis, particle 1 free.
State spring_state(const Model& model, double e, double u) {
  State s = initial_state(model);
  const Vec3 axis = (s.x.col(1) - s.x.col(0)).normalized();
  s.x.col(1) = s.x.col(0) + (model.springs.rest[0] + e) * axis;
  s.v.col(1) = u * axis;
  return s;
}

// One step's matrix on (e, h u) from states without history (a_n from the forces).
Eigen::Matrix2d one_step_matrix(const Model& model, double h) {
  Eigen::Matrix2d m;
  for (int col = 0; col < 2; ++col) {
    State s = spring_state(model, col == 0 ? 1e-6 : 0.0, col == 1 ? 1e-6 / h : 0.0);
    Workspace ws;
    const StepReport r = step(model, s, kImex, h, ws);
    EXPECT_TRUE(r.stats.converged);
    const Vec3 axis = (s.x.col(1) - s.x.col(0)).normalized();
    m(0, col) = ((s.x.col(1) - s.x.col(0)).norm() - model.springs.rest[0]) / 1e-6;
    m(1, col) = h * (s.v.col(1) - s.v.col(0)).dot(axis) / 1e-6;
  }
  return m;
}

TEST(Imex, AmplifiesByItsClosedFormAndIsStableBelowTwoOverOmegaWhateverTheDamping) {
  for (double c : {0.0, 2.0, 20.0, 200.0, 2e4}) {
    const Model model = build_model(load_spring_scene({damping(c), "cloth.initial_stretch=0"}));
    const double w = std::sqrt(model.springs.ks[0] / model.mass[1]), cm = c / model.mass[1];
    for (double wh : {0.1, 1.0, 1.9, 1.99}) {
      const double h = wh / w, d = 1.0 / (1.0 + 0.5 * h * cm);
      const Eigen::Matrix2d m = one_step_matrix(model, h);
      EXPECT_NEAR(m.determinant(), d * d, 1e-7) << "c " << c << " w h " << wh;
      EXPECT_NEAR(m.trace(), 1.0 + d * d - d * (1.0 + d) * wh * wh / 2.0, 1e-7) << "c " << c << " w h " << wh;
      const double radius = Eigen::EigenSolver<Eigen::Matrix2d>(m).eigenvalues().cwiseAbs().maxCoeff();
      EXPECT_LE(radius, 1.0 + 1e-9) << "c " << c << " w h " << wh;
    }
    // Just past the elastic limit it grows undamped; the dampers move the limit out, never in.
    const double radius = Eigen::EigenSolver<Eigen::Matrix2d>(one_step_matrix(model, 2.02 / w))
                              .eigenvalues().cwiseAbs().maxCoeff();
    if (c == 0.0) EXPECT_GT(radius, 1.0);
    // imex_limit is where imex_matrix's spectral radius crosses 1; the registry predicts the
    // undamped mode's (its w_max and c_max bound different modes).
    const double limit = imex_limit(w, cm);
    EXPECT_GE(limit * w, 2.0 - 1e-9) << "c " << c;
    EXPECT_NEAR(integrator_info(kImex).linear_limit(w, cm, {}) * w, 2.0, 1e-9);
    for (double side : {1.0 - 1e-6, 1.0 + 1e-6}) {
      double m[9];
      imex_matrix(side * limit, w, cm, m);
      const Eigen::Matrix3d M = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m);
      const double r = Eigen::EigenSolver<Eigen::Matrix3d>(M).eigenvalues().cwiseAbs().maxCoeff();
      if (side < 1.0) EXPECT_LE(r, 1.0 + 1e-9) << "c " << c;
      else EXPECT_GT(r, 1.0) << "c " << c;
    }
    if (c > 0.0) {
      EXPECT_LT(analysis::step_matrix_limit(velocity_verlet_matrix, w, cm) * w, 2.0) << "c " << c;
      EXPECT_LT(analysis::symplectic_euler_limit(w, cm) * w, 2.0) << "c " << c;
    }
  }
}

TEST(Imex, StepMatrixIsTheStepTheCodeTakes) {
  // imex_matrix (what the registry's limit reads) on (u, u', a), a fresh state's a being
  // -w^2 e - c u: on (e, h u) the step the code takes on the spring.
  const Model model = build_model(load_spring_scene({damping(20.0), "cloth.initial_stretch=0"}));
  const double w = 10.0, cm = 20.0, h = 0.15;
  double m[9];
  imex_matrix(h, w, cm, m);
  Eigen::Matrix2d on_eu;
  for (int row = 0; row < 2; ++row) {
    on_eu(row, 0) = m[3 * row] - w * w * m[3 * row + 2];
    on_eu(row, 1) = m[3 * row + 1] - cm * m[3 * row + 2];
  }
  const Eigen::Matrix2d code = one_step_matrix(model, h);
  EXPECT_NEAR(code(0, 0), on_eu(0, 0), 1e-8);
  EXPECT_NEAR(code(0, 1), on_eu(0, 1) / h, 1e-8);
  EXPECT_NEAR(code(1, 0), h * on_eu(1, 0), 1e-8);
  EXPECT_NEAR(code(1, 1), on_eu(1, 1), 1e-8);
}

TEST(Imex, NeverGainsEnergyWithTheDampersAtAnyStableStep) {
  // Like Verlet's, its energy swings within a step's band; with the dampers the band's top
  // falls period after period, from light to heavy damping and up to w h = 1.99.
  for (double c : {2.0, 20.0, 2e4}) {
    const Model model = build_model(load_spring_scene({damping(c), "cloth.initial_stretch=1e-3"}));
    for (double wh : {0.05, 0.5, 1.99}) {
      const int period = static_cast<int>(std::ceil(2.0 * M_PI / wh));
      const std::vector<double> E = energy_history(model, kImex, step_for(model, wh), 40 * period);
      double top = E.front();
      // (until round-off: the extension's ulp, ~1e-16 m against e0 = 1e-3 m, is E0 x 1e-26)
      for (std::size_t from = 1; from + period <= E.size() && top > 1e-20 * E.front(); from += period) {
        const double next = *std::max_element(E.begin() + from, E.begin() + from + period);
        EXPECT_LE(next, top * (1.0 + 1e-12)) << "c " << c << " w h " << wh << " step " << from;
        top = next;
      }
      EXPECT_LT(E.back(), E.front());
    }
  }
}

TEST(Imex, EveryStepOfTheBarrierDrapeMakesNoEnergyBeforeThePush) {
  // drape_smooth before the ball's first push: static colliders, so the total energy (the
  // barrier's counted) may only fall, frame to frame, by the dampers' and the drag's work.
  const Model model = build_model(load_scene(scene_path("drape_smooth.yaml")));
  clothsim::Run run(model, kImex, 1e-4);
  double E = run.metrics().energies.total(), largest_rise = 0.0;
  for (int frame = 1; frame <= 24; ++frame) {
    ASSERT_TRUE(run.advance_to(frame / 30.0)) << run.divergence()->reason;
    const double now = run.metrics().energies.total();
    largest_rise = std::max(largest_rise, (now - E) / std::abs(E));
    E = now;
  }
  EXPECT_EQ(run.totals().unconverged_steps, 0);
  EXPECT_LE(largest_rise, 1e-9);
}

TEST(Imex, CostsOneForcePassAStepAfterTheFirstAndRestartsAfterAWrite) {
  const Model model = sheet_with_two_spheres();
  State state = initial_state(model);
  Workspace ws;
  const StepStats first = step(model, state, kImex, 1e-4, ws).stats;
  EXPECT_EQ(first.force_evals, 2);
  EXPECT_EQ(first.assemblies, 2);
  for (int i = 0; i < 3; ++i) {  // the force pass and the matrix at x_{n+1} carried on
    const StepStats s = step(model, state, kImex, 1e-4, ws).stats;
    EXPECT_EQ(s.force_evals, 1);
    EXPECT_EQ(s.assemblies, 1);
    EXPECT_GT(s.cg_iterations, 0);
  }
  EXPECT_EQ(nominal_force_evals(kImex), 1);
  state.v.col(5) += Vec3(0.0, 0.1, 0.0);  // a write from outside: the carried pass is stale
  State fresh = state;
  fresh.history = {};
  Workspace ws2;
  EXPECT_EQ(step(model, state, kImex, 1e-4, ws).stats.force_evals, 2);
  step(model, fresh, kImex, 1e-4, ws2);
  EXPECT_EQ(state.x, fresh.x);
  EXPECT_EQ(state.v, fresh.v);
}

TEST(Imex, ACopiedStateContinuesBitForBit) {
  const Model model = sheet_with_two_spheres();
  State a = initial_state(model);
  Workspace ws, ws2;
  for (int i = 0; i < 5; ++i) step(model, a, kImex, 1e-4, ws);
  State b = a;  // ws2 holds no matrix for it: it assembles what ws reuses, to the same bits
  EXPECT_EQ(step(model, b, kImex, 1e-4, ws2).stats.assemblies, 2);
  EXPECT_EQ(step(model, a, kImex, 1e-4, ws).stats.assemblies, 1);
  for (int i = 0; i < 5; ++i) step(model, a, kImex, 1e-4, ws), step(model, b, kImex, 1e-4, ws2);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.v, b.v);
}

TEST(Imex, RunsTheBarrierAndTheProjection) { EXPECT_EQ(barrier_refusal(kImex), ""); }

TEST(Imex, IntegratesParticlesAndSpheresTogether) { expect_whole_state_integrated(kImex, 0.0, 1e-9); }

}  // namespace
}  // namespace clothsim::testing
