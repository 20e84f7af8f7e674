// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick one at
// run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "integrators/cg_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cstddef>

#include "integrators/cg_kernels.h"
#include "spring_layout.h"  // kSpringLanePad

#ifndef CLOTHSIM_CG_KERNELS_ONCE  // this part once, not once per target
#define CLOTHSIM_CG_KERNELS_ONCE
namespace clothsim {
namespace {
// Partial sums: entry k goes to sum k mod kSums. Every target's lane count divides it and
// every vector starts at a multiple of its lane count, so each sum sees the same terms in the
// same order on every target.
constexpr std::size_t kSums = kSpringLanePad;
}  // namespace
}  // namespace clothsim
#endif

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
static_assert(HWY_MAX_BYTES / sizeof(double) <= kSums, "a vector's lanes are consecutive sums");

namespace {

// sums[k mod kSums] += value, for the N lanes of a vector at entry k (k a multiple of N).
HWY_INLINE void Accumulate(double* HWY_RESTRICT sums, std::size_t k, V value) {
  const D d;
  const std::size_t j = k % kSums;
  hn::StoreU(hn::Add(hn::LoadU(d, sums + j), value), d, sums + j);
}

}  // namespace

void Dot(const double* HWY_RESTRICT a, const double* HWY_RESTRICT b, std::size_t n,
         double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t k = 0;
  for (; k + N <= n; k += N) Accumulate(sums, k, hn::Mul(hn::LoadU(d, a + k), hn::LoadU(d, b + k)));
  for (; k < n; ++k) sums[k % kSums] += a[k] * b[k];
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
    sums[k % kSums] += r[k] * r[k];
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
    sums[i % kSums] += r0 * z0 + r1 * z1 + r2 * z2;
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

namespace {
double total(const double* sums) {  // in a fixed order
  double out = 0.0;
  for (std::size_t j = 0; j < kSums; ++j) out += sums[j];
  return out;
}
}  // namespace

double simd_dot(const double* a, const double* b, std::size_t n) {
  alignas(64) double sums[kSums] = {};
  HWY_DYNAMIC_DISPATCH(Dot)(a, b, n, sums);
  return total(sums);
}

double simd_update_iterate(double* x, double* r, const double* p, const double* q, double alpha,
                           std::size_t n) {
  alignas(64) double sums[kSums] = {};
  HWY_DYNAMIC_DISPATCH(UpdateIterate)(x, r, p, q, alpha, n, sums);
  return total(sums);
}

double simd_jacobi(const double* inverse, std::size_t B, const double* r, double* z) {
  alignas(64) double sums[kSums] = {};
  HWY_DYNAMIC_DISPATCH(Jacobi)(inverse, B, r, z, sums);
  return total(sums);
}

void simd_xpby(double* p, const double* z, double beta, std::size_t n) {
  HWY_DYNAMIC_DISPATCH(Xpby)(p, z, beta, n);
}

}  // namespace clothsim
#endif  // HWY_ONCE
