#include "method_memory.h"

#include <algorithm>
#include <cmath>

#include "core/implicit/newton_solve.h"

namespace clothsim {

namespace {
// Each run's own arrays per particle, from peak RSS at 256², 1024² and 2048² (BENCHMARKS.md,
// "Memory estimate"): the explicit family's state and scratch, and what each method keeps
// beyond them (midpoint's half-step state; RK4's four stages; XPBD's constraint passes and
// their grid sets; VBD's colouring, per-vertex blocks and the grid sweep's colour-major copies:
// measured 385 and 670 B a particle over the explicit family between 256² and 1024²).
constexpr double kExplicitPerParticle = 176;
constexpr double kMidpointExtra = 80, kRk4Extra = 128, kXpbdExtra = 448, kVbdExtra = 700;
// VBD's accelerated iterations (vbd.chebyshev_rho > 0) keep two more iterates: 48 B a
// particle (measured 47.5 at 1024²).
constexpr double kVbdAcceleratedExtra = 48;
// Projective dynamics' prefactored global matrix (a scalar sparse LDLT of P x P, AMD-ordered,
// kept for refactoring, and its supernodal panels in float, which the solve reads) and its
// solves: measured 2165, 2365 and 2646 B a particle over an explicit run at 256², 512² and
// 1024² (2606, 2928 and 3323 with the panels in double), bounded by 140 log2 P (an empirical
// bound on the drape's grids, not a theory).
constexpr double kPdPerLog2 = 140;
constexpr double kFinalStatePerParticle = 64;  // a kept copy of x, v and inverse masses
// velocity_verlet's and yoshida4's State carries the last force pass (StepHistory: a, and the
// x, v and inverse masses it belongs to): 80 B a body, in the run and in a kept copy.
constexpr double kVerletHistoryPerBody = 80;
// implicit_euler's State also carries its warm start: three velocity changes, the last
// linearisation's positions and inverse masses (160 B a body), its spring lengths (8 B each).
constexpr double kImplicitFinalPerParticle = 160, kImplicitFinalPerSpring = 8;
constexpr double kImplicitPerParticle = 560, kImplicitPerSpring = 144;
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

// An adaptive pair's vectors of y = (x, v) (48 B a body each): y itself, its stages'
// derivatives, and Odeint's controlled stepper's derivative, new state and error (3 more);
// counted from the steppers' members, not measured.
constexpr double kPairVectorPerBody = 48;
MethodMemory pair_memory(const MemorySizes& n, int stages) {
  return {kExplicitPerParticle * n.particles + kPairVectorPerBody * (stages + 4) * n.bodies,
          kFinalStatePerParticle * n.bodies};
}

MethodMemory explicit_family_plus(const MemorySizes& n, double extra_per_particle) {
  return {(kExplicitPerParticle + extra_per_particle) * n.particles, kFinalStatePerParticle * n.bodies};
}
}  // namespace

MethodMemory explicit_family_memory(const MemorySizes& n) { return explicit_family_plus(n, 0.0); }
MethodMemory midpoint_memory(const MemorySizes& n) { return explicit_family_plus(n, kMidpointExtra); }
MethodMemory rk4_memory(const MemorySizes& n) { return explicit_family_plus(n, kRk4Extra); }
MethodMemory verlet_memory(const MemorySizes& n) {
  MethodMemory m = explicit_family_plus(n, 0.0);
  m.run += kVerletHistoryPerBody * n.bodies;
  m.final_state += kVerletHistoryPerBody * n.bodies;
  return m;
}
MethodMemory bs3_memory(const MemorySizes& n) { return pair_memory(n, 4); }
MethodMemory dopri5_memory(const MemorySizes& n) { return pair_memory(n, 7); }
MethodMemory rkf78_memory(const MemorySizes& n) { return pair_memory(n, 13); }
MethodMemory xpbd_memory(const MemorySizes& n) { return explicit_family_plus(n, kXpbdExtra); }
MethodMemory vbd_memory(const MemorySizes& n) {
  const bool accelerated = n.solvers.vbd.chebyshev_rho > 0.0;
  return explicit_family_plus(n, kVbdExtra + (accelerated ? kVbdAcceleratedExtra : 0.0));
}
MethodMemory projective_dynamics_memory(const MemorySizes& n) {
  return explicit_family_plus(n, kPdPerLog2 * std::log2(std::max(n.particles, 2.0)));
}
// What the Newton step's preconditioner keeps: the sparse factor when `cholesky` may build
// one; the V-cycle's levels (the Galerkin operators' 3x3 blocks, the smoother's and the
// transfers' vectors, the finest level's spring form for its Chebyshev smoother): peak RSS
// less the rest of this estimate is 2510 and 2715 B a particle at 128² and 256² (the spring
// form about 600 of it; 2200 at 1024² before it), counted as 3000 (the totals then 1.05x the
// peaks, BENCHMARKS.md "Memory estimate"); block Jacobi's inverse blocks are in the base.
constexpr double kMultigridPerParticle = 3000;

double preconditioner_bytes(const MemorySizes& n) {
  switch (resolved_preconditioner(n.preconditioner, n.particles)) {
    case PreconditionerKind::Multigrid: return kMultigridPerParticle * n.particles;
    case PreconditionerKind::BlockJacobi: return 0.0;
    default: return implicit_factor_bytes(n.particles, n.springs);
  }
}

// From ImplicitDef::single_from particles the matrix also keeps a float copy for CG's mat-vec
// (linear/block_matrix.h): five floats and a byte a spring slot, R's six floats a particle
// (peak RSS at 256²: 9.4 MiB over e0a69cb's, 150 B a particle; BENCHMARKS.md #37, round s37).
constexpr double kSinglePerParticle = 24, kSinglePerSpring = 21;

double single_copy_bytes(const MemorySizes& n) {
  if (n.particles < ImplicitDef{}.single_from) return 0.0;
  return kSinglePerParticle * n.particles + kSinglePerSpring * n.springs;
}

MethodMemory implicit_euler_memory(const MemorySizes& n) {
  return {(kExplicitPerParticle + kImplicitPerParticle) * n.particles + kImplicitPerSpring * n.springs +
              single_copy_bytes(n) + preconditioner_bytes(n),
          kImplicitFinalPerParticle * n.bodies + kImplicitFinalPerSpring * n.springs};
}

// The implicit family beyond implicit_euler: a pseudo-start and the update's copies of x_n, v_n
// and a (Workspace's x1, v1, x2, v2, a1: 120 B a body) in the run; in State, bdf2's step before
// (x, v: 48 B a body, lengths 8 B a spring) or the carried acceleration (24 B), with the end
// state it belongs to (56 B): bdf2's, the larger, is counted for all. Not yet measured.
constexpr double kFamilyRunPerBody = 120, kFamilyHistoryPerBody = 104, kFamilyHistoryPerSpring = 8;

MethodMemory implicit_family_memory(const MemorySizes& n) {
  MethodMemory m = implicit_euler_memory(n);
  const double history = kFamilyHistoryPerBody * n.bodies + kFamilyHistoryPerSpring * n.springs;
  m.run += kFamilyRunPerBody * n.bodies + history;
  m.final_state += history;
  return m;
}

// imex: the explicit family's arrays, implicit_euler's cache (its block-Jacobi solves build no
// factor), Verlet's carried force pass, and the damping matrix's own pattern beside the cache's
// Newton one: 64 B a spring, from peak RSS at 256² (233 MB, where the rest of this estimate
// says 215).
constexpr double kImexDampingPerSpring = 64;
MethodMemory imex_memory(const MemorySizes& n) {
  MethodMemory m = verlet_memory(n);
  m.run += kImplicitPerParticle * n.particles + (kImplicitPerSpring + kImexDampingPerSpring) * n.springs +
           single_copy_bytes(n);
  return m;
}

}  // namespace clothsim
