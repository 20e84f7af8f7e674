// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick one at
// run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/linear/cg_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

#include "cg_kernels.h"
#include "partial_sums-inl.h"


HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using partial_sums::Accumulate;

void Dot(const double* HWY_RESTRICT a, const double* HWY_RESTRICT b, std::size_t n,
         double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t k = 0;
  for (; k + N <= n; k += N) Accumulate(sums, k, hn::Mul(hn::LoadU(d, a + k), hn::LoadU(d, b + k)));
  for (; k < n; ++k) sums[k % kPartialSums] += a[k] * b[k];
}

void UpdateIterate(double* HWY_RESTRICT x, double* HWY_RESTRICT r, const double* HWY_RESTRICT p,
                   const double* HWY_RESTRICT q, double alpha, std::size_t n,
                   double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V a = hn::Set(d, alpha);
  std::size_t k = 0;
  for (; k + N <= n; k += N) {
    hn::StoreU(hn::Add(hn::LoadU(d, x + k), hn::Mul(a, hn::LoadU(d, p + k))), d, x + k);
    const V rk = hn::Sub(hn::LoadU(d, r + k), hn::Mul(a, hn::LoadU(d, q + k)));
    hn::StoreU(rk, d, r + k);
    Accumulate(sums, k, hn::Mul(rk, rk));
  }
  for (; k < n; ++k) {
    x[k] = x[k] + alpha * p[k];
    r[k] = r[k] - alpha * q[k];
    sums[k % kPartialSums] += r[k] * r[k];
  }
}

void Jacobi(const double* HWY_RESTRICT inverse, std::size_t B, const double* HWY_RESTRICT r,
            double* HWY_RESTRICT z, double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const double* HWY_RESTRICT xx = inverse;
  const double* HWY_RESTRICT yy = xx + B;
  const double* HWY_RESTRICT zz = yy + B;
  const double* HWY_RESTRICT xy = zz + B;
  const double* HWY_RESTRICT xz = xy + B;
  const double* HWY_RESTRICT yz = xz + B;
  std::size_t i = 0;
  for (; i + N <= B; i += N) {
    V r0, r1, r2;
    hn::LoadInterleaved3(d, r + 3 * i, r0, r1, r2);
    const V a = hn::LoadU(d, xx + i), b = hn::LoadU(d, yy + i), c = hn::LoadU(d, zz + i);
    const V e = hn::LoadU(d, xy + i), f = hn::LoadU(d, xz + i), g = hn::LoadU(d, yz + i);
    // Eigen's 3 x 3 times 3 order: row i of D^-1 times r, left to right.
    const V z0 = hn::Add(hn::Add(hn::Mul(a, r0), hn::Mul(e, r1)), hn::Mul(f, r2));
    const V z1 = hn::Add(hn::Add(hn::Mul(e, r0), hn::Mul(b, r1)), hn::Mul(g, r2));
    const V z2 = hn::Add(hn::Add(hn::Mul(f, r0), hn::Mul(g, r1)), hn::Mul(c, r2));
    hn::StoreInterleaved3(z0, z1, z2, d, z + 3 * i);
    Accumulate(sums, i, hn::Add(hn::Add(hn::Mul(r0, z0), hn::Mul(r1, z1)), hn::Mul(r2, z2)));
  }
  for (; i < B; ++i) {
    const double r0 = r[3 * i], r1 = r[3 * i + 1], r2 = r[3 * i + 2];
    const double z0 = xx[i] * r0 + xy[i] * r1 + xz[i] * r2;
    const double z1 = xy[i] * r0 + yy[i] * r1 + yz[i] * r2;
    const double z2 = xz[i] * r0 + yz[i] * r1 + zz[i] * r2;
    z[3 * i] = z0;
    z[3 * i + 1] = z1;
    z[3 * i + 2] = z2;
    sums[i % kPartialSums] += r0 * z0 + r1 * z1 + r2 * z2;
  }
}

void InvertBlocks(const double* HWY_RESTRICT blocks, std::size_t B, double* HWY_RESTRICT inverse,
                  double* HWY_RESTRICT soa) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V one = hn::Set(d, 1.0);
  HWY_ALIGN double in[6][kPartialSums];
  HWY_ALIGN double out[6][kPartialSums];
  for (std::size_t i = 0; i < B; i += N) {
    const std::size_t lanes = i + N <= B ? N : B - i;
    for (std::size_t j = 0; j < N; ++j) {  // the 6 entries of each block (the rest: identity)
      const double* D3 = blocks + 9 * (i + (j < lanes ? j : 0));
      in[0][j] = D3[0], in[1][j] = D3[4], in[2][j] = D3[8];
      in[3][j] = D3[3], in[4][j] = D3[6], in[5][j] = D3[7];
    }
    const V a = hn::Load(d, in[0]), b = hn::Load(d, in[1]), c = hn::Load(d, in[2]);
    const V e = hn::Load(d, in[3]), f = hn::Load(d, in[4]), g = hn::Load(d, in[5]);  // xy, xz, yz
    // The adjugate of the symmetric block [a e f; e b g; f g c], over its determinant.
    const V c00 = hn::Sub(hn::Mul(b, c), hn::Mul(g, g));
    const V c11 = hn::Sub(hn::Mul(a, c), hn::Mul(f, f));
    const V c22 = hn::Sub(hn::Mul(a, b), hn::Mul(e, e));
    const V c01 = hn::Sub(hn::Mul(f, g), hn::Mul(e, c));
    const V c02 = hn::Sub(hn::Mul(e, g), hn::Mul(b, f));
    const V c12 = hn::Sub(hn::Mul(e, f), hn::Mul(a, g));
    const V det = hn::Add(hn::Add(hn::Mul(a, c00), hn::Mul(e, c01)), hn::Mul(f, c02));
    const V inv_det = hn::Div(one, det);
    const V entry[6] = {hn::Mul(c00, inv_det), hn::Mul(c11, inv_det), hn::Mul(c22, inv_det),
                        hn::Mul(c01, inv_det), hn::Mul(c02, inv_det), hn::Mul(c12, inv_det)};
    for (int k = 0; k < 6; ++k) {
      hn::Store(entry[k], d, out[k]);
      if (lanes == N) hn::StoreU(entry[k], d, soa + k * B + i);
      else std::copy(out[k], out[k] + lanes, soa + k * B + i);
    }
    for (std::size_t j = 0; j < lanes; ++j) {
      double* D3 = inverse + 9 * (i + j);
      D3[0] = out[0][j], D3[4] = out[1][j], D3[8] = out[2][j];
      D3[1] = D3[3] = out[3][j];
      D3[2] = D3[6] = out[4][j];
      D3[5] = D3[7] = out[5][j];
    }
  }
}

void Xpby(double* HWY_RESTRICT p, const double* HWY_RESTRICT z, double beta, std::size_t n) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V b = hn::Set(d, beta);
  std::size_t k = 0;
  for (; k + N <= n; k += N) hn::StoreU(hn::Add(hn::LoadU(d, z + k), hn::Mul(b, hn::LoadU(d, p + k))), d, p + k);
  for (; k < n; ++k) p[k] = z[k] + beta * p[k];
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(Dot);
HWY_EXPORT(UpdateIterate);
HWY_EXPORT(Jacobi);
HWY_EXPORT(Xpby);
HWY_EXPORT(InvertBlocks);

double simd_dot(const double* a, const double* b, std::size_t n) {
  alignas(64) double sums[kPartialSums] = {};
  HWY_DYNAMIC_DISPATCH(Dot)(a, b, n, sums);
  return partial_sums_total(sums);
}

double simd_update_iterate(double* x, double* r, const double* p, const double* q, double alpha,
                           std::size_t n) {
  alignas(64) double sums[kPartialSums] = {};
  HWY_DYNAMIC_DISPATCH(UpdateIterate)(x, r, p, q, alpha, n, sums);
  return partial_sums_total(sums);
}

double simd_jacobi(const double* inverse, std::size_t B, const double* r, double* z) {
  alignas(64) double sums[kPartialSums] = {};
  HWY_DYNAMIC_DISPATCH(Jacobi)(inverse, B, r, z, sums);
  return partial_sums_total(sums);
}

void simd_invert_blocks(const double* blocks, std::size_t B, double* inverse, double* soa) {
  HWY_DYNAMIC_DISPATCH(InvertBlocks)(blocks, B, inverse, soa);
}

void simd_xpby(double* p, const double* z, double beta, std::size_t n) {
  HWY_DYNAMIC_DISPATCH(Xpby)(p, z, beta, n);
}

}  // namespace clothsim
#endif  // HWY_ONCE
