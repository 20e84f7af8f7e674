// The physical settings a Model carries as a scene gave them: ground, collision, the implicit
// solver's options and the divergence bounds. Plain values; defaults live here and nowhere else.
// Units are SI: m, s, kg, N/m, N s/m.
#pragma once

#include <Eigen/Core>

namespace clothsim {

using Vec3 = Eigen::Vector3d;

struct GroundDef {
  double height = 0.0;       // m, plane y = height
  double restitution = 0.0;  // [0, 1]
  double friction = 0.0;     // Coulomb coefficient, >= 0
};

// How contacts act (docs/integrators.md, "Two contact models"): `projection`, the course's
// response after each step (collisions.h); `barrier`, a smooth potential inside every force
// evaluation and every solve (contact/barrier_kernels.h).
enum class ContactModel { Projection, Barrier };

struct CollisionDef {
  ContactModel model = ContactModel::Projection;
  double margin = 0.01;                // m, contact distance beyond a surface (the seed's 0.01; projection)
  bool sphere_sphere = false;          // resolve sphere-sphere contacts
  double sphere_restitution = 0.8;     // C_R between spheres (projection)
  double barrier_distance = 0.01;      // m, d-hat: where the barrier activates (barrier)
  // N/m, the barrier's stiffness b''(d-hat / 2) (barrier); 0: chosen from the scene so that
  // the cloth's mean particle weight rests at d-hat / 2 (build_model resolves it).
  double barrier_stiffness = 0.0;
  double friction_velocity = 1e-3;     // m/s, IPC's eps_v: below it friction is smoothed (barrier)
};

enum class ImplicitSolver { Newton, FixedPoint };

// How implicit_euler's Newton solve runs. A scene or lane asks for Baraff & Witkin's step with
// an iteration count of 1 (`newton_max_iterations: 1`, `implicit_euler@1/60:1`); the solver
// reads the mode, never the count.
enum class NewtonMode {
  Converged,     // globalised Newton on the exact Hessian to newton_tolerance
  BaraffWitkin,  // Baraff & Witkin 1998: one linearised step on the projected Hessian, taken whole
};

// The Newton step's linear solve (`implicit.preconditioner`, docs/scenes.md): PCG with block
// Jacobi alone; block Jacobi until a sparse Cholesky factor pays for itself (the rent-against-
// buy of newton_solve.h); the multigrid V-cycle (linear/multigrid_preconditioner.h); or auto,
// which picks by the sheet's size (kJacobiFromParticles, measured in BENCHMARKS.md, #37).
enum class PreconditionerKind { Auto, BlockJacobi, Cholesky, Multigrid };

struct ImplicitDef {
  ImplicitSolver solver = ImplicitSolver::Newton;
  PreconditionerKind preconditioner = PreconditionerKind::Auto;
  // Per step; 1 = Baraff-Witkin's single linearised step. The default is a backstop: a step
  // stops when it converges or stalls (core/implicit/newton_solve.h, StallWatch).
  int newton_max_iterations = 500;
  double newton_tolerance = 1e-6;  // on |M dv - h f(x+h(v+dv), v+dv)| relative to |h f|
  int cg_max_iterations = 200;
  double cg_tolerance = 1e-8;      // relative residual of each linear solve
  int fixed_point_iterations = 1;  // solver: fixed_point; 1 reproduces the course framework
  // From this many particles on, CG's mat-vec reads a float copy of the matrix (linear/
  // block_matrix.h, SpringBlockMatrix::single; BENCHMARKS.md #37, round s37): the sheets whose
  // numbers outgrow the cache. Below, the double numbers, and a factor of the matrix is CG's
  // exact inverse. Not a scene key: tests move it.
  int single_from = 128 * 128;
  // From this many particles on, Newton's directions are held within a trust radius and CG's
  // forcing term is sqrt(|r|) (newton_solve.h, TrustRadius; BENCHMARKS.md #37, round s34);
  // below, the line search alone and the forcing term |r|. Not a scene key: tests move it.
  int trust_region_from = 128 * 128;
  // With the trust region, each particle's share of a Newton direction moves its end position
  // h |d_i| at most this many shortest rest lengths (newton_solve.h, cap_particle_steps;
  // BENCHMARKS.md #37, round s35); 0: no cap. Not a scene key: tests move it.
  double direction_cap = 0.15;

  NewtonMode newton_mode() const {
    return newton_max_iterations == 1 ? NewtonMode::BaraffWitkin : NewtonMode::Converged;
  }
};

struct DivergenceDef {
  double max_strain = 10.0;        // stop when a spring exceeds (1 + max_strain) x rest length
  double max_energy_factor = 1e4;  // stop when kinetic energy exceeds factor x the scene's energy scale
};

}  // namespace clothsim
