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

namespace {
// A scene's sizes, as the methods' memory terms read them.
struct Sizes {
  double particles, springs, bodies;  // bodies: particles and spheres
  const SceneDef& scene;
};

// What one method costs: its run's own arrays (state, scratch, systems, factors) and the final
// state it keeps for --state. One function per method, so each set of terms can move into the
// method's integrator registry row as it is.
struct MethodMemory {
  double run = 0.0;
  double final_state = 0.0;
};

MethodMemory explicit_family_memory(const Sizes& n, double extra_per_particle) {
  return {(kExplicitPerParticle + extra_per_particle) * n.particles, kFinalStatePerParticle * n.bodies};
}
MethodMemory midpoint_memory(const Sizes& n) { return explicit_family_memory(n, kMidpointExtra); }
MethodMemory rk4_memory(const Sizes& n) { return explicit_family_memory(n, kRk4Extra); }
MethodMemory xpbd_memory(const Sizes& n) { return explicit_family_memory(n, kXpbdExtra); }
MethodMemory vbd_memory(const Sizes& n) {
  const bool accelerated = n.scene.solvers.vbd.chebyshev_rho > 0.0;
  return explicit_family_memory(n, kVbdExtra + (accelerated ? kVbdAcceleratedExtra : 0.0));
}
MethodMemory projective_dynamics_memory(const Sizes& n) {
  return explicit_family_memory(n, kPdPerLog2 * std::log2(std::max(n.particles, 2.0)));
}
MethodMemory implicit_euler_memory(const Sizes& n) {
  return {(kExplicitPerParticle + kImplicitPerParticle) * n.particles + kImplicitPerSpring * n.springs +
              implicit_factor_bytes(n.particles, n.springs),
          kImplicitFinalPerParticle * n.bodies + kImplicitFinalPerSpring * n.springs};
}

MethodMemory method_memory(const SceneDef& scene, IntegratorKind kind) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  const Sizes n{particles, static_cast<double>(spring_count(scene.cloth)),
                particles + static_cast<double>(scene.spheres.size()), scene};
  switch (kind) {
    case IntegratorKind::ExplicitEuler:
    case IntegratorKind::SymplecticEuler: return explicit_family_memory(n, 0.0);
    case IntegratorKind::Midpoint: return midpoint_memory(n);
    case IntegratorKind::Rk4: return rk4_memory(n);
    case IntegratorKind::Xpbd: return xpbd_memory(n);
    case IntegratorKind::Vbd: return vbd_memory(n);
    case IntegratorKind::ProjectiveDynamics: return projective_dynamics_memory(n);
    case IntegratorKind::ImplicitEuler: return implicit_euler_memory(n);
  }
  return explicit_family_memory(n, 0.0);
}
}  // namespace

double run_bytes(const SceneDef& scene, IntegratorKind kind) { return method_memory(scene, kind).run; }

double final_state_bytes(const SceneDef& scene, IntegratorKind kind) {
  return method_memory(scene, kind).final_state;
}

}  // namespace clothsim
