// The single spring of scenes/spring.yaml as a test bench for the integrators.
//
// One spring (k, l0) between a pinned particle and a free one of mass m, damper c, no
// gravity, released at rest stretched by e0 along the spring. The free end moves on the
// spring's axis only, where the force -k e - c e' is linear in the extension e = l - l0:
//     m e'' + c e' + k e = 0,   e(0) = e0, e'(0) = 0,
// with roots r = -zeta w +- w sqrt(zeta^2 - 1), w = sqrt(k/m), zeta = c / (2 sqrt(k m)).
// So every integrator's exact solution is known (convergence orders), and undamped
// (c = 0) its step on (e, e'/w) is the method's amplification factor R(z) at z = i w h:
// energy multiplies by |R|^2 per step for the one-step methods whose step matrix is a
// scaled rotation (explicit Euler, midpoint, RK4, backward Euler, fixed point).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "core/model/diagnostics.h"
#include "core/model/model.h"
#include "core/run/simulation.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::testing {

inline std::string spring_scene_path() { return std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml"; }

struct Oscillator {
  double k, c, m, e0, rest;
  double omega() const { return std::sqrt(k / m); }
  double zeta() const { return c / (2.0 * std::sqrt(k * m)); }

  // The two characteristic roots (complex conjugates when underdamped).
  std::complex<double> root(int sign) const {
    const double w = omega(), z = zeta();
    return -z * w + sign * w * std::sqrt(std::complex<double>(z * z - 1.0));
  }
  // Largest decay or oscillation rate: what a step must resolve.
  double fastest_rate() const { return std::max(std::abs(root(1)), std::abs(root(-1))); }

  // e(t), e'(t): A e^{r1 t} + B e^{r2 t} with A + B = e0, r1 A + r2 B = 0 (distinct roots).
  void exact(double t, double& e, double& edot) const {
    const std::complex<double> r1 = root(1), r2 = root(-1);
    const std::complex<double> A = -r2 * e0 / (r1 - r2), B = e0 - A;
    const std::complex<double> E1 = std::exp(r1 * t), E2 = std::exp(r2 * t);
    e = (A * E1 + B * E2).real();
    edot = (A * r1 * E1 + B * r2 * E2).real();
  }
};

// Loads scenes/spring.yaml with `--set` overrides and reads the oscillator it defines.
inline SceneDef load_spring_scene(const std::vector<std::string>& overrides = {}) {
  return load_scene(spring_scene_path(), overrides);
}

inline Oscillator oscillator_of(const SceneDef& scene) {
  Oscillator o;
  o.k = scene.cloth.structural->stiffness;
  o.c = scene.cloth.structural->damping;
  o.m = scene.cloth.particle_mass;
  o.e0 = scene.cloth.initial_stretch;
  o.rest = scene.cloth.size_x;  // nx = 2: the two particles are size_x apart at rest
  return o;
}

// Extension and its rate from a state of the spring scene (particle 0 pinned at the origin
// side, particle 1 free).
inline double extension(const Oscillator& o, const State& s) {
  return (s.x.col(1) - s.x.col(0)).norm() - o.rest;
}
inline double extension_rate(const State& s) {
  const Vec3 u = (s.x.col(1) - s.x.col(0)).normalized();
  return (s.v.col(1) - s.v.col(0)).dot(u);
}

// Error at the end of a run in phase space, scaled to a length: sqrt(de^2 + (de'/w)^2).
// Measuring both components keeps the error from vanishing by chance at a phase crossing.
inline double phase_error(const Oscillator& o, const State& s) {
  double e, edot;
  o.exact(s.t, e, edot);
  const double de = extension(o, s) - e;
  const double dv = (extension_rate(s) - edot) / o.omega();
  return std::hypot(de, dv);
}

// Runs the spring scene with integrator `kind` at step h to time T (a whole number of steps)
// through clothsim::Run, exactly as `clothsim run` does, and returns the phase-space error.
inline double error_at(const SceneDef& scene, IntegratorKind kind, double h, double T) {
  const Model model = build_model(scene);
  Run run(model, kind, h);
  EXPECT_TRUE(run.advance_to(T)) << integrator_name(kind) << " diverged at h = " << h;
  EXPECT_NEAR(run.state().t, T, 1e-9 * T);
  return phase_error(oscillator_of(scene), run.state());
}

// Observed orders log2(err(h) / err(h/2)) for h0, h0/2, h0/4, h0/8 (three orders).
inline std::vector<double> observed_orders(const SceneDef& scene, IntegratorKind kind,
                                           double h0, double T) {
  std::vector<double> err;
  for (int halvings = 0; halvings <= 3; ++halvings)
    err.push_back(error_at(scene, kind, h0 / std::pow(2.0, halvings), T));
  std::vector<double> orders;
  for (std::size_t i = 0; i + 1 < err.size(); ++i) orders.push_back(std::log2(err[i] / err[i + 1]));
  return orders;
}

// Mechanical energy of the spring scene (kinetic + spring; no gravity in it).
inline double energy(const Model& model, const State& s) { return compute_energies(model, s).total(); }

// Energy after each of `steps` steps at h, driven through clothsim::step (not Run, which
// would stop a run at its divergence bound: these tests want to see the growth).
inline std::vector<double> energy_history(const Model& model, IntegratorKind kind, double h,
                                          int steps) {
  State state = initial_state(model);
  Workspace ws;
  std::vector<double> E{energy(model, state)};
  for (int n = 0; n < steps; ++n) {
    step(model, state, kind, h, ws);
    E.push_back(energy(model, state));
  }
  return E;
}

// The undamped spring released at extension e0. The motion is linear only while the spring
// keeps a positive length (|e| < l0 = 1 m), so tests that grow or shrink the energy by many
// orders of magnitude start small; the state's absolute precision (~1e-16 m on positions of
// order 1 m) is what bounds how far down a decay can be followed.
inline Model undamped_spring_model(double e0 = 1e-3, const std::vector<std::string>& extra = {}) {
  std::ostringstream stretch;
  stretch << "cloth.initial_stretch=" << e0;
  std::vector<std::string> overrides{"cloth.springs.structural.damping=0", stretch.str()};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return build_model(load_spring_scene(overrides));
}
inline double step_for(const Model& model, double wh) {
  const double k = model.springs.ks[0], m = model.mass[1];
  return wh / std::sqrt(k / m);
}

}  // namespace clothsim::testing
