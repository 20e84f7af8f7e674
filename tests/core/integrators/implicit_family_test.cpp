// The implicit family (integrators/implicit_family.h) against its theory: order 2 on the
// damped spring; on x'' = -w^2 x the step matrices the code takes, against their closed forms
// (implicit midpoint and the trapezoid |R| = 1 at every w h, generalized-alpha's spectral
// radius tending to rho_inf, BDF2's root inside the unit circle); energy (implicit midpoint
// keeps the undamped spring's to round-off, BDF2 and backward Euler lose it, BDF2 less); and
// on the barrier drape at one step per frame, every step converged and no energy made.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include "test_support.h"
#include "core/implicit/step_potential.h"
#include "core/integrators/implicit_family.h"
#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kMidpoint = IntegratorKind::ImplicitMidpoint;
constexpr IntegratorKind kNewmark = IntegratorKind::Newmark;
constexpr IntegratorKind kAlpha = IntegratorKind::GeneralizedAlpha;
constexpr IntegratorKind kBdf2 = IntegratorKind::Bdf2;
constexpr IntegratorKind kFamily[] = {kMidpoint, kNewmark, kAlpha, kBdf2};

// The undamped spring's state with extension e and rate u along its axis (particle 1 free).
State spring_state(const Model& model, double e, double u) {
  State s = initial_state(model);
  const Vec3 axis = (s.x.col(1) - s.x.col(0)).normalized();
  const double rest = model.springs.rest[0];
  s.x.col(1) = s.x.col(0) + (rest + e) * axis;
  s.v.col(1) = u * axis;
  return s;
}

Vec3 axis_of(const State& s) { return (s.x.col(1) - s.x.col(0)).normalized(); }
double ext(const Model& model, const State& s) { return (s.x.col(1) - s.x.col(0)).norm() - model.springs.rest[0]; }
double rate(const State& s) { return (s.v.col(1) - s.v.col(0)).dot(axis_of(s)); }

// One step's matrix on (e, u) from a state without history (a_n from the forces, no step before).
Eigen::Matrix2d one_step_matrix(const Model& model, IntegratorKind kind, double h) {
  Eigen::Matrix2d m;
  for (int col = 0; col < 2; ++col) {
    State s = spring_state(model, col == 0 ? 1e-3 : 0.0, col == 1 ? 1e-3 : 0.0);
    Workspace ws;
    step(model, s, kind, h, ws);
    m(0, col) = ext(model, s) / 1e-3;
    m(1, col) = rate(s) / 1e-3;
  }
  return m;
}

double spectral_radius(const Eigen::MatrixXd& m) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(m).eigenvalues().cwiseAbs().maxCoeff();
}

SceneDef undamped_spring_scene() { return load_spring_scene({"cloth.springs.structural.damping=0"}); }

// Each method's observed orders on `scene` from |r| h = 0.05 down three halvings, printed.
void expect_second_order(const SceneDef& scene, const char* what) {
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
  std::printf("implicit family orders on the %s spring:", what);
  for (const IntegratorKind kind : kFamily) {
    std::printf(" %s", std::string(integrator_name(kind)).c_str());
    for (double p : observed_orders(scene, kind, h0, T)) {
      std::printf(" %.3f", p);
      EXPECT_NEAR(p, 2.0, 0.1) << integrator_name(kind);
    }
    std::printf(";");
  }
  std::printf("\n");
}

TEST(ImplicitFamily, EveryMethodConvergesAtSecondOrderOnTheDampedSpring) {
  const SceneDef scene = load_spring_scene();
  ASSERT_GT(oscillator_of(scene).zeta(), 0.0);
  expect_second_order(scene, "damped");
}

TEST(ImplicitFamily, ConvergesAtSecondOrderOnTheUndampedSpringToo) { expect_second_order(undamped_spring_scene(), "undamped"); }

TEST(ImplicitMidpointAndTrapezoid, AmplifyByTheCayleyFactorOfModulusOneAtEveryStep) {
  // R(z) = (1 + z/2) / (1 - z/2) at z = i w h: |R| = 1, arg R = 2 atan(w h / 2). The real
  // step matrix on (e, u) has eigenvalues R and its conjugate: det 1, trace 2 Re R.
  const Model model = undamped_spring_model();
  for (const IntegratorKind kind : {kMidpoint, kNewmark}) {
    for (double wh : {0.01, 0.3, 1.0, 3.0, 30.0, 1000.0}) {
      const Eigen::Matrix2d m = one_step_matrix(model, kind, step_for(model, wh));
      const double q = wh * wh / 4.0;
      EXPECT_NEAR(m.determinant(), 1.0, 1e-9) << integrator_name(kind) << " w h " << wh;
      EXPECT_NEAR(m.trace(), 2.0 * (1.0 - q) / (1.0 + q), 1e-9) << integrator_name(kind) << " w h " << wh;
    }
  }
}

// Generalized-alpha's step on (e, h u, h^2 a) (scaled so that every column moves the spring by
// the same small length: the spring stays linear at any w h) from states whose carried
// acceleration is set.
Eigen::Matrix3d alpha_step_matrix(const Model& model, IntegratorKind kind, double h) {
  const double unit = 1e-6;
  Eigen::Matrix3d m;
  for (int col = 0; col < 3; ++col) {
    State s = spring_state(model, col == 0 ? unit : 0.0, col == 1 ? unit / h : 0.0);
    s.history.a = Eigen::Matrix3Xd::Zero(3, model.num_bodies());
    s.history.a.col(1) = (col == 2 ? unit / (h * h) : 0.0) * axis_of(s);
    s.history.record(kind, s);
    Workspace ws;
    step(model, s, kind, h, ws);
    m(0, col) = ext(model, s) / unit;
    m(1, col) = h * rate(s) / unit;
    m(2, col) = h * h * s.history.a.col(1).dot(axis_of(s)) / unit;
  }
  return m;
}

// The textbook algorithm on x'' = -w^2 x (Chung & Hulbert 1993), written out on its own:
// (1 - am) a1 + am a0 = -w^2 ((1 - af) x1 + af x0) with Newmark's x1, v1.
// On (x, h v, h^2 a), with W = w h.
Eigen::Matrix3d textbook_alpha_matrix(const AlphaMethod& p, double W) {
  Eigen::Matrix3d m;
  for (int col = 0; col < 3; ++col) {
    const double x0 = col == 0, v0 = col == 1, a0 = col == 2;
    const double xp = x0 + v0 + (0.5 - p.beta) * a0;  // x1 = xp + beta a1
    const double a1 = (-W * W * ((1 - p.af) * xp + p.af * x0) - p.am * a0) / ((1 - p.am) + W * W * (1 - p.af) * p.beta);
    m(0, col) = xp + p.beta * a1;
    m(1, col) = v0 + (1 - p.gamma) * a0 + p.gamma * a1;
    m(2, col) = a1;
  }
  return m;
}

TEST(GeneralizedAlpha, TakesChungAndHulbertsStepAndItsSpectralRadiusTendsToRhoInf) {
  const Model base = undamped_spring_model();
  for (double rho : {0.0, 0.5, 0.8, 1.0}) {
    Model model = base;
    model.methods.generalized_alpha.rho_inf = rho;
    const AlphaMethod p = generalized_alpha_method(generalized_alpha_params(model));
    for (double wh : {0.1, 1.0, 10.0, 1e4}) {
      const double h = step_for(model, wh);
      const Eigen::Matrix3d m = alpha_step_matrix(model, kAlpha, h);
      EXPECT_LT((m - textbook_alpha_matrix(p, wh)).cwiseAbs().maxCoeff(), 1e-6) << "rho " << rho << " w h " << wh;
      // (at rho_inf = 1 the eigenvalue -1 is double at infinity: rounding moves it by sqrt(eps))
      EXPECT_LE(spectral_radius(m), 1.0 + 1e-7) << "rho " << rho << " w h " << wh;
    }
    // At w h -> infinity the textbook matrix's eigenvalues are -rho_inf (a defective pair:
    // Chung & Hulbert's choice merges them) and af / (af - 1) = -rho_inf: its spectral radius
    // is rho_inf, approached slowly (the pair splits as a root of the perturbation).
    EXPECT_NEAR(spectral_radius(textbook_alpha_matrix(p, 1e9)), rho, 1e-4) << "rho " << rho;
    const double near = spectral_radius(alpha_step_matrix(model, kAlpha, step_for(model, 1e4)));
    const double nearer = spectral_radius(alpha_step_matrix(model, kAlpha, step_for(model, 1e6)));
    EXPECT_NEAR(near, rho, 3e-3) << "rho " << rho;
    EXPECT_NEAR(nearer, rho, 1e-3) << "rho " << rho;  // (the defective pair amplifies rounding too)
    // and barely damps a resolved mode: 1 - O((w h)^3)
    EXPECT_GT(spectral_radius(alpha_step_matrix(model, kAlpha, step_for(model, 0.05))), 1.0 - 1e-4) << "rho " << rho;
  }
}

// BDF2's step on (e_{n-1}, u_{n-1}, e_n, u_n) from states whose step before is set.
Eigen::Matrix4d bdf2_step_matrix(const Model& model, double h) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  for (int col = 0; col < 4; ++col) {
    const double unit = 1e-3;
    State before = spring_state(model, col == 0 ? unit : 0.0, col == 1 ? unit : 0.0);
    State s = spring_state(model, col == 2 ? unit : 0.0, col == 3 ? unit : 0.0);
    s.history.x_before = before.x;
    s.history.v_before = before.v;
    step_lengths(model, before.x, s.history.length_before);
    s.history.h = h;
    s.history.record(kBdf2, s);
    m(0, col) = ext(model, s) / unit;
    m(1, col) = rate(s) / unit;
    Workspace ws;
    step(model, s, kBdf2, h, ws);
    m(2, col) = ext(model, s) / unit;
    m(3, col) = rate(s) / unit;
  }
  return m;
}

TEST(Bdf2, DampsEveryModeByItsClosedFormRootAndTendsToZeroAtLargeSteps) {
  // Its roots on z = +-i w h: (1 - 2z/3) zeta^2 - 4/3 zeta + 1/3 = 0; the larger |zeta| < 1 at
  // every w h > 0 (A-stable, damping), -> 0 as w h grows (L-stable).
  const Model model = undamped_spring_model();
  double last = 1.0;
  for (double wh : {0.1, 0.5, 1.0, 3.0, 10.0, 100.0, 1e4}) {
    const std::complex<double> z(0.0, wh), a = 1.0 - 2.0 * z / 3.0;
    const std::complex<double> disc = std::sqrt(16.0 / 9.0 - 4.0 * a / 3.0);
    const double root = std::max(std::abs((4.0 / 3.0 + disc) / (2.0 * a)), std::abs((4.0 / 3.0 - disc) / (2.0 * a)));
    const double measured = spectral_radius(bdf2_step_matrix(model, step_for(model, wh)));
    EXPECT_NEAR(measured, root, 1e-7) << "w h " << wh;
    EXPECT_LT(measured, 1.0) << "w h " << wh;
    EXPECT_LT(measured, last) << "w h " << wh;
    last = measured;
  }
  EXPECT_LT(last, 0.01);
}

TEST(ImplicitMidpoint, KeepsTheUndampedSpringsEnergyToRoundOffAtEveryStepSize) {
  const Model model = undamped_spring_model();
  for (double wh : {0.1, 1.0, 10.0, 100.0}) {
    const std::vector<double> E = energy_history(model, kMidpoint, step_for(model, wh), 2000);
    for (double e : E) ASSERT_NEAR(e / E.front(), 1.0, 1e-9) << "w h " << wh;
  }
}

TEST(Bdf2, LosesTheUndampedSpringsEnergyButFarLessThanBackwardEulerAtAResolvedStep) {
  // Over 200 steps at w h = 0.1 (three periods) backward Euler keeps (1 + (w h)^2)^-200 = 14 %
  // of the energy, BDF2 (its root 1 - (w h)^4 / 4 per step, roughly) about 99 %. (Past w h ~ 1
  // BDF2 damps more than backward Euler per step: both tend to 0, L-stable.)
  const Model model = undamped_spring_model();
  for (double wh : {0.1, 0.3, 0.5}) {
    const std::vector<double> bdf2 = energy_history(model, kBdf2, step_for(model, wh), 200);
    const std::vector<double> euler = energy_history(model, kBackwardEuler, step_for(model, wh), 200);
    EXPECT_LT(bdf2.back(), bdf2.front()) << "w h " << wh;
    EXPECT_LT(euler.back(), bdf2.back()) << "w h " << wh;
  }
  const std::vector<double> bdf2 = energy_history(model, kBdf2, step_for(model, 0.1), 200);
  const std::vector<double> euler = energy_history(model, kBackwardEuler, step_for(model, 0.1), 200);
  EXPECT_GT(bdf2.back(), 0.95 * bdf2.front());
  EXPECT_NEAR(euler.back() / euler.front(), std::pow(1.0 / 1.01, 200), 1e-3);
}

TEST(ImplicitFamily, EveryStepOfTheBarrierDrapeConvergesAtOneStepPerFrameAndMakesNoEnergy) {
  // drape_smooth before its first push (t < 1 s): static colliders, so the total energy
  // (kinetic, springs, gravity, barrier) may only fall, frame to frame, by the methods'
  // dissipation, the dampers' and the drag's.
  const Model model = build_model(load_scene(scene_path("drape_smooth.yaml")));
  for (const IntegratorKind kind : kFamily) {
    clothsim::Run run(model, kind, 1.0 / 60.0);
    double E = run.metrics().energies.total();
    double largest_rise = 0.0;
    for (int frame = 1; frame <= 54; ++frame) {
      ASSERT_TRUE(run.advance_to(frame / 60.0)) << integrator_name(kind) << ": " << run.divergence()->reason;
      const double now = run.metrics().energies.total();
      largest_rise = std::max(largest_rise, (now - E) / std::abs(E));
      E = now;
    }
    const RunTotals& t = run.totals();
    EXPECT_EQ(t.unconverged_steps, 0) << integrator_name(kind) << ": largest residual " << t.max_residual;
    EXPECT_LE(largest_rise, 1e-9) << integrator_name(kind);
  }
}

TEST(ImplicitFamily, AnEventOrAnOutsideWriteRestartsTheHistoryAsAFreshStateWould) {
  const Model model = sheet_with_two_spheres();
  for (const IntegratorKind kind : {kNewmark, kAlpha, kBdf2}) {
    State state = initial_state(model);
    Workspace ws;
    step(model, state, kind, 1e-3, ws);
    step(model, state, kind, 1e-3, ws);
    state.v.col(5) += Vec3(0.0, 0.1, 0.0);
    State fresh = state;
    fresh.history = {};
    Workspace ws2;
    step(model, state, kind, 1e-3, ws);
    step(model, fresh, kind, 1e-3, ws2);
    EXPECT_LT((state.x - fresh.x).cwiseAbs().maxCoeff(), 1e-12) << integrator_name(kind);
    EXPECT_LT((state.v - fresh.v).cwiseAbs().maxCoeff(), 1e-10) << integrator_name(kind);
  }
}

TEST(ImplicitFamily, ACopiedStateContinuesBitForBit) {
  const Model model = sheet_with_two_spheres();
  for (const IntegratorKind kind : kFamily) {
    State a = initial_state(model);
    Workspace ws, ws2;
    for (int i = 0; i < 4; ++i) step(model, a, kind, 1.0 / 60, ws);
    State b = a;
    for (int i = 0; i < 4; ++i) step(model, a, kind, 1.0 / 60, ws), step(model, b, kind, 1.0 / 60, ws2);
    EXPECT_EQ(a.x, b.x) << integrator_name(kind);
    EXPECT_EQ(a.v, b.v) << integrator_name(kind);
  }
}

TEST(ImplicitFamily, IntegratesParticlesAndSpheresTogether) {
  // Exact on a free fall (second order in a constant field), to the solve's tolerance; BDF2
  // keeps its backward Euler start's offset, 3/4 g h^2 (the error's roots 1 and 1/3): 1.5e-4
  // of the fall after 100 steps.
  for (const IntegratorKind kind : {kMidpoint, kNewmark, kAlpha}) expect_whole_state_integrated(kind, 0.0, 1e-6);
  expect_whole_state_integrated(kBdf2, 0.015, 1e-6);
}

}  // namespace
}  // namespace clothsim::testing
