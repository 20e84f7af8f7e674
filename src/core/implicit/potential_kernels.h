// The implicit step's passes over the springs in SIMD, over a SpringLayout's grid-stencil
// families (spring_layout.h), through Google Highway with runtime dispatch, built the way the
// force pass is (spring_kernels.h): blocks of positions, every family per block, a per-thread
// window of structure-of-arrays scratch that slides with the blocks, contiguous loads of the
// springs' ends p .. p+L-1 and p+offset .. p+offset+L-1 (no gathers), their contributions added
// into two sums (at a and at b) so that no two lanes of a store share a particle and a
// particle's terms are summed in (block, family) order whatever the lane count.
//
// Three passes over the springs, each what the scalar reference (step_potential.h,
// sparse_system.h) does for a spring, with the same operations in the same order and no fused
// multiply-add (this file is compiled with -ffp-contract=off and calls Mul and Add, never
// MulAdd), and one over the bodies (Phi's inertia, gravity and drag terms):
//  - the start-of-step lengths l_n, by slot;
//  - Phi's spring terms and their gradient at the end-of-step positions y;
//  - the Newton matrix's spring blocks applied to a vector (the CG mat-vec), with each block's
//    (u, alpha, beta) read by slot (their assembly: assembly_kernels.h).
// Per-spring data are stored by the layout's slot (spring_layout.h): family f's position k at
// slot_first + k, zeros at the positions without a spring, which every pass masks out.
//
// Numerics: only the order in which a particle's (or Phi's) terms are summed differs from the
// scalar reference, so the two agree to rounding. Phi's sum is taken in 16 partial sums, the
// spring at position k into sum k mod 16 (every target's lane count divides 16), added in
// order at the end: like the lanes, it does not depend on the target. So every target (SCALAR
// .. AVX3) gives the same bits, and a run is bit-identical from run to run, thread to thread and
// across x86-64 CPUs.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "step_form.h"
#include "core/springs/spring_layout.h"

namespace clothsim {

// length[slot] (layout.num_slots) = each family spring's |x_a - x_b| (0 at a slot without a
// spring; `others` untouched). Returns their largest l / l0 (1 when none is stretched, NaN
// when a length is NaN).
double family_step_lengths(const SpringLayout& layout, const Eigen::Matrix3Xd& x, double* length);

struct FamilyPotential {
  double phi = 0.0;        // J, sum over the families' springs of E_s (step_spring_energy)
  double magnitude = 0.0;  // J, sum of E_s + |T_s| l_s (step_potential.h's PotentialValue)
};

// The families' terms of the step potential at end-of-step positions y (3 x B): returns their
// energies; gradient (3 x B) += dE_s/ddv = h T u at a and -h T u at b (none where l <= 0), h
// the form's h_e and T's damper rate (l - l_ref) / damper_h (step_form.h). start_length: l_ref
// by slot (family_step_lengths' l_n for backward Euler). With end_length, also writes there
// what family_step_lengths(layout, y, end_length) would, bit for bit (the lengths at y).
FamilyPotential family_step_potential(const SpringLayout& layout, const Eigen::Matrix3Xd& y,
                                      const double* start_length, const StepForm& form,
                                      Eigen::Matrix3Xd& gradient, double* end_length = nullptr);

// The largest l / l0 of the families' lengths by slot: what family_step_lengths returned when
// it wrote them.
double family_strain(const SpringLayout& layout, const double* length);

// Phi's body terms and the end-of-step positions, the bodies in SIMD: y (3 x B) = x + h (v + dv),
// and gradient (3 x B) = the bodies' terms of Phi's gradient, m dv - h m g + drag_h c v (written:
// the spring passes add to it after), zero on immovable bodies; returns the terms' energies
// (inertia, gravity's work, drag's dissipation; step_potential.h's PotentialValue), summed in
// kSpringLanePad partial sums (body i into sum i mod 16), added in order at the end.
struct BodyArgs {
  const double* x;          // (3 x B) the start of the step
  const double* v;          // (3 x B)
  const double* dv;         // (3 x B) the iterate
  const double* inv_mass;   // (B)
  const std::uint8_t* gravity_on;  // (B)
  std::size_t bodies = 0;     // B
  std::size_t particles = 0;  // the first P bodies have air drag
  double h = 0.0, drag = 0.0;
  double drag_h = 0.0;  // s, StepForm::drag_h (h for backward Euler)
  double gravity[3] = {0.0, 0.0, 0.0};
};
FamilyPotential body_terms(const BodyArgs& args, Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient);

// The matrix's diagonal blocks D_i and the families' spring blocks G_s = alpha u u^T + beta I,
// by slot (ux, uy, uz, alpha, beta: layout.num_slots each), applied to p: writes out_i (3 x B,
// sized by the caller) = D_i p_i + the sum of G_s p_b over the springs with a = i and of
// G_s p_a over those with b = i, for the particles 0 .. F - 1 (F returned; from F on, which no
// spring reaches, out is the caller's). D from SpringBlockMatrix::diag_soa.
struct FamilyBlocks {
  const double* ux;
  const double* uy;
  const double* uz;
  const double* alpha;
  const double* beta;
  const double* diag;  // (6 B) entries xx, yy, zz, xy, xz, yz, entry e of body i at e B + i
  std::size_t bodies;  // B
};
std::size_t family_multiply(const SpringLayout& layout, const FamilyBlocks& blocks,
                            const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& out);

// The same product from SpringBlockMatrix::single's float numbers (block_matrix.h says why),
// widened, with products and sums in double: R_i (D_i plus the blocks at i's family springs)
// in place of D_i, and each spring's G_s on the difference of its ends, out_i = R_i p_i + the
// sum of G_s (p_b - p_a) over the springs with a = i and of G_s (p_a - p_b) over those with
// b = i, which is D_i p_i + the G_s p of the other ends.
struct FamilySingleBlocks {
  const float* ux;
  const float* uy;
  const float* uz;
  const float* alpha;
  const float* beta;
  const std::uint8_t* spring;  // (slots) 1 where the slot holds a spring
  const float* rest;   // (6 B) R, entries as FamilyBlocks::diag's
  std::size_t bodies;  // B
};
std::size_t family_multiply_single(const SpringLayout& layout, const FamilySingleBlocks& blocks,
                                   const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& out);


// The Highway target these kernels run on this CPU.
const char* potential_kernel_target();

}  // namespace clothsim
