#include "memory_estimate.h"

#include <algorithm>
#include <cmath>

namespace clothsim {

namespace {
// The Model's arrays per particle: mass and inverse mass 16 B, gravity flag 1 B, position and
// velocity 48 B, two triangles 24 B (89 B, rounded up); per spring two indices, rest length,
// stiffness, damping and type (33 B, rounded up); per scripted action (TimedAction) 48 B.
constexpr double kModelPerParticle = 96, kModelPerSpring = 40, kPerAction = 64;
// Each run's own arrays per particle, from peak RSS at 256², 1024² and 2048² (BENCHMARKS.md,
// "Memory estimate"): the explicit family's state and scratch, and what each method keeps
// beyond them (midpoint's half-step state; RK4's four stages; XPBD's constraint passes; VBD's
// colouring and per-vertex blocks).
constexpr double kExplicitPerParticle = 176;
constexpr double kMidpointExtra = 80, kRk4Extra = 128, kXpbdExtra = 256, kVbdExtra = 296;
// VBD's accelerated iterations (vbd.chebyshev_rho > 0) keep two more iterates: 48 B a
// particle (measured 47.5 at 1024²).
constexpr double kVbdAcceleratedExtra = 48;
// Projective dynamics' prefactored global matrix (a scalar sparse LDLT of P x P, AMD-ordered,
// kept for refactoring, and its supernodal panels, which the solve reads) and its solves:
// measured 2606, 2928 and 3323 B a particle over an explicit run at 256², 512² and 1024²,
// bounded by 175 log2 P (an empirical bound on the drape's grids, not a theory).
constexpr double kPdPerLog2 = 175;
constexpr double kFinalStatePerParticle = 64;  // a kept copy of x, v and inverse masses
// implicit_euler's State also carries its warm start: three velocity changes, the last
// linearisation's positions and inverse masses (160 B a body), its spring lengths (8 B each).
constexpr double kImplicitFinalPerParticle = 160, kImplicitFinalPerSpring = 8;
constexpr double kImplicitPerParticle = 560, kImplicitPerSpring = 144;
constexpr double kPerSphere = 4096;  // measured 3.9 kB, mostly the YAML tree of its entry
// implicit_euler's sparse factor, when a step needs it: L's 3x3 blocks (76 B each) number
// 27, 49, 69, 88 and 116 per particle at 25², 64², 128², 256² and 300² (AMD on the grid), so
// 8 log2(P) per particle bounds them; never more than the solver's cap (newton_solve.cpp), and
// none where even one block per matrix pair (a particle and its springs) passes the cap: the
// solver then never analyses the pattern.
constexpr double kFactorBlockBytes = 80, kMaxFactorBytes = 512.0 * 1024 * 1024;

double implicit_factor_bytes(double particles, double springs) {
  if (kFactorBlockBytes * (particles + springs) > kMaxFactorBytes) return 0.0;
  return std::min(kFactorBlockBytes * particles * 8.0 * std::log2(std::max(particles, 2.0)), kMaxFactorBytes);
}
}  // namespace

std::int64_t spring_count(const ClothDef& c) {
  const std::int64_t nx = c.nx, ny = c.ny;
  const auto positive = [](std::int64_t n) { return n > 0 ? n : 0; };
  std::int64_t springs = 0;
  if (c.structural) springs += positive(nx - 1) * ny + nx * positive(ny - 1);
  if (c.shear) springs += 2 * positive(nx - 1) * positive(ny - 1);
  if (c.bend) springs += positive(nx - 2) * ny + nx * positive(ny - 2);
  return springs;
}

double model_bytes(const SceneDef& scene) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  double actions = 0.0;  // the timeline: keyframes, pins and unpins
  for (const SphereDef& s : scene.spheres) actions += static_cast<double>(s.motion.size());
  for (const EventDef& e : scene.events) actions += static_cast<double>(e.pin.size() + e.unpin.size());
  return kModelPerParticle * particles + kModelPerSpring * static_cast<double>(spring_count(scene.cloth)) +
         kPerSphere * static_cast<double>(scene.spheres.size()) + kPerAction * actions;
}

double run_bytes(const SceneDef& scene, IntegratorKind kind) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  const double springs = static_cast<double>(spring_count(scene.cloth));
  double per_particle = kExplicitPerParticle, bytes = 0.0;
  switch (kind) {
    case IntegratorKind::ExplicitEuler:
    case IntegratorKind::SymplecticEuler: break;
    case IntegratorKind::Midpoint: per_particle += kMidpointExtra; break;
    case IntegratorKind::Rk4: per_particle += kRk4Extra; break;
    case IntegratorKind::Xpbd: per_particle += kXpbdExtra; break;
    case IntegratorKind::Vbd:
      per_particle += kVbdExtra + (scene.solvers.vbd.chebyshev_rho > 0.0 ? kVbdAcceleratedExtra : 0.0);
      break;
    case IntegratorKind::ProjectiveDynamics:
      per_particle += kPdPerLog2 * std::log2(std::max(particles, 2.0));
      break;
    case IntegratorKind::ImplicitEuler:
      per_particle += kImplicitPerParticle;
      bytes = kImplicitPerSpring * springs + implicit_factor_bytes(particles, springs);
      break;
  }
  return per_particle * particles + bytes;
}

double final_state_bytes(const SceneDef& scene, IntegratorKind kind) {
  const double bodies = static_cast<double>(scene.cloth.nx) * scene.cloth.ny + static_cast<double>(scene.spheres.size());
  if (kind != IntegratorKind::ImplicitEuler) return kFinalStatePerParticle * bodies;
  return kImplicitFinalPerParticle * bodies + kImplicitFinalPerSpring * static_cast<double>(spring_count(scene.cloth));
}

}  // namespace clothsim
