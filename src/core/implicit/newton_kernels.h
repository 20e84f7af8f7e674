// The Newton loop's own vector passes in SIMD (implicit_euler.cpp), through Google Highway with
// runtime dispatch, as the CG loop's are (cg_kernels.h): the norms the convergence test is
// measured against, the judgement of the next step's first guess, the distance to the Newton
// matrix's linearisation point, and the step's final update. Each was a scalar loop with one
// running sum (a chain of dependent additions a body) or an Eigen SSE2 pass of its own. At the
// drape's 1e-4 s on 64 x 64, newton_step and NewtonSolve::iterate, with these passes inlined,
// were 16.2 % of the step's profile; with the kernels the two and the kernels are 13.8 %, a
// few per cent of CPU (BENCHMARKS.md).
//
// The vectors are 3 x B matrices' data (body i's xyz at 3 i), the per-body weights B doubles.
// Sums are taken in fixed partial sums (partial_sums-inl.h: body i, or entry k, into sum i or
// k mod 16), with no fused multiply-add (-ffp-contract=off): every Highway target gives the same
// bits. Against the scalar expressions they replace (the tests' references) only the order of
// the sums differs, which moved the drape's iteration counts by rounding (1 s at 25 x 25: 8 141
// -> 8 148 Newton, 15 072 -> 15 054 CG iterations).
#pragma once

#include <cstddef>

namespace clothsim {

// sum_i weight_i |v_i|^2 over B bodies, leaving out those of weight 0: |M dv|^2 with the
// weights 1 / w_i^2 (immovable bodies, w_i = 0, are not unknowns).
double simd_weighted_norm2(const double* weight, const double* v, std::size_t B);

// sum_i |mass_i dv_i - r_i|^2 over the B bodies of mass_i != 0: |h f|^2 at an iterate whose
// residual is r = M dv - h f.
double simd_impulse_norm2(const double* mass, const double* dv, const double* r, std::size_t B);

// How far dv (n entries) lies from what each extrapolation through the last steps' dv
// predicted: miss[0] = |dv - a|^2 (a = dv_n), miss[1] = |dv - (2 a - b)|^2 (b = dv_{n-1}),
// miss[2] = |dv - (3 (a - b) + c)|^2 (c = dv_{n-2}); b and c may be null (then miss[1], miss[2]
// are left as they are), c only with b.
void simd_guess_misses(const double* dv, const double* a, const double* b, const double* c, std::size_t n,
                       double miss[3]);

// max_i |y_i - y0_i|^2 over P bodies (0 for none; NaN if any coordinate difference is NaN).
double simd_max_distance2(const double* y, const double* y0, std::size_t P);

// v += dv, then x += h v (n entries each): backward Euler's update of the state.
void simd_finish_step(double* x, double* v, const double* dv, double h, std::size_t n);

}  // namespace clothsim
