// The conjugate-gradient loop's vector passes in SIMD (conjugate_gradient.h), through Google
// Highway with runtime dispatch, fused where one pass can serve two steps of the loop:
//  - x += alpha p and r -= alpha q, with |r|^2 (three passes of Eigen code before);
//  - the block-Jacobi solve z = D^-1 r, with r . z (two);
//  - p = z + beta p, and a dot product;
//  - the block-Jacobi preconditioner's 3 x 3 inverses.
// The vectors are flat arrays (a 3 x B matrix's n = 3 B doubles, or B bodies' xyz). Each sum
// is taken in 16 fixed partial sums (partial_sums-inl.h: entry k into sum k mod 16; for r . z, body i into sum i
// mod 16), added in order at the end, with no fused multiply-add (this file is compiled with
// -ffp-contract=off): every Highway target gives the same bits. Against Eigen's expressions
// (the scalar reference the tests hold them to, within 1e-12 relative) only the order of the
// sums differs; the element-wise results are the same bits.
#pragma once

#include <Eigen/Core>

#include <cstddef>

namespace clothsim {

// sum_k a_k b_k over n entries.
double simd_dot(const double* a, const double* b, std::size_t n);
// sum_k a_k b_k over two 3 x B matrices, by simd_dot.
inline double matrix_dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return simd_dot(a.data(), b.data(), static_cast<std::size_t>(a.size()));
}

// x += alpha p, r -= alpha q (n entries each); returns |r|^2 after.
double simd_update_iterate(double* x, double* r, const double* p, const double* q, double alpha,
                           std::size_t n);

// z_i = D_i^-1 r_i for B bodies (D^-1 symmetric, 6 entries xx, yy, zz, xy, xz, yz of body i at
// e B + i: SpringBlockMatrix::diag_inverse_soa; r, z: 3 x B); returns r . z.
double simd_jacobi(const double* inverse, std::size_t B, const double* r, double* z);

// The inverses of B symmetric 3 x 3 blocks (column-major, 9 doubles each: the block-Jacobi
// preconditioner's diag_projected), through their adjugates and one division by the
// determinant: written as blocks (9 B) and as structure of arrays (6 B, as simd_jacobi reads).
// Eigen's closed-form 3 x 3 inverse gives the same numbers to rounding.
void simd_invert_blocks(const double* blocks, std::size_t B, double* inverse, double* soa);

// p = z + beta p (n entries).
void simd_xpby(double* p, const double* z, double beta, std::size_t n);

}  // namespace clothsim
