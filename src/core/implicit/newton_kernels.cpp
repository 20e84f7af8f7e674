// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick one at
// run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/implicit/newton_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <limits>

#include "newton_kernels.h"
#include "core/linear/partial_sums-inl.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using partial_sums::Accumulate;

namespace {

// x^2 + y^2 + z^2, summed as Eigen sums a 3-vector's squaredNorm.
HWY_INLINE V Norm2(V x, V y, V z) { return hn::Add(hn::Add(hn::Mul(x, x), hn::Mul(y, y)), hn::Mul(z, z)); }
inline double Norm2(double x, double y, double z) { return x * x + y * y + z * z; }

}  // namespace

void WeightedNorm2(const double* HWY_RESTRICT weight, const double* HWY_RESTRICT v, std::size_t B,
                   double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t i = 0;
  for (; i + N <= B; i += N) {
    V x, y, z;
    hn::LoadInterleaved3(d, v + 3 * i, x, y, z);
    const V w = hn::LoadU(d, weight + i);
    Accumulate(sums, i, hn::IfThenElseZero(hn::Ne(w, hn::Zero(d)), hn::Mul(Norm2(x, y, z), w)));
  }
  for (; i < B; ++i)
    if (weight[i] != 0.0) sums[i % kPartialSums] += Norm2(v[3 * i], v[3 * i + 1], v[3 * i + 2]) * weight[i];
}

void ImpulseNorm2(const double* HWY_RESTRICT mass, const double* HWY_RESTRICT dv, const double* HWY_RESTRICT r,
                  std::size_t B, double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t i = 0;
  for (; i + N <= B; i += N) {
    V x, y, z, rx, ry, rz;
    hn::LoadInterleaved3(d, dv + 3 * i, x, y, z);
    hn::LoadInterleaved3(d, r + 3 * i, rx, ry, rz);
    const V m = hn::LoadU(d, mass + i);
    const V f = Norm2(hn::Sub(hn::Mul(m, x), rx), hn::Sub(hn::Mul(m, y), ry), hn::Sub(hn::Mul(m, z), rz));
    Accumulate(sums, i, hn::IfThenElseZero(hn::Ne(m, hn::Zero(d)), f));
  }
  for (; i < B; ++i) {
    const double m = mass[i];
    if (m == 0.0) continue;
    const double* p = dv + 3 * i;
    const double* q = r + 3 * i;
    sums[i % kPartialSums] += Norm2(m * p[0] - q[0], m * p[1] - q[1], m * p[2] - q[2]);
  }
}

// sums: three sets of kPartialSums, for the last dv, the line and the parabola.
void GuessMisses(const double* HWY_RESTRICT dv, const double* HWY_RESTRICT a, const double* HWY_RESTRICT b,
                 const double* HWY_RESTRICT c, std::size_t n, double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V three = hn::Set(d, 3.0);
  double* HWY_RESTRICT last_sums = sums;
  double* HWY_RESTRICT line_sums = sums + kPartialSums;
  double* HWY_RESTRICT parabola_sums = sums + 2 * kPartialSums;
  std::size_t k = 0;
  for (; k + N <= n; k += N) {
    const V x = hn::LoadU(d, dv + k), an = hn::LoadU(d, a + k);
    const V last = hn::Sub(x, an);
    Accumulate(last_sums, k, hn::Mul(last, last));
    if (!b) continue;
    const V slope = hn::Sub(an, hn::LoadU(d, b + k));
    const V line = hn::Sub(last, slope);  // x - (2 a - b), as x - a - (a - b)
    Accumulate(line_sums, k, hn::Mul(line, line));
    if (!c) continue;
    const V parabola = hn::Sub(x, hn::Add(hn::Mul(three, slope), hn::LoadU(d, c + k)));
    Accumulate(parabola_sums, k, hn::Mul(parabola, parabola));
  }
  for (; k < n; ++k) {
    const double last = dv[k] - a[k];
    last_sums[k % kPartialSums] += last * last;
    if (!b) continue;
    const double slope = a[k] - b[k];
    const double line = last - slope;
    line_sums[k % kPartialSums] += line * line;
    if (!c) continue;
    const double parabola = dv[k] - (3.0 * slope + c[k]);
    parabola_sums[k % kPartialSums] += parabola * parabola;
  }
}

// Writes the largest squared distance and whether any was NaN into out[0], out[1].
void MaxDistance2(const double* HWY_RESTRICT y, const double* HWY_RESTRICT y0, std::size_t P,
                  double* HWY_RESTRICT out) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  V largest = hn::Zero(d);
  auto nan = hn::Ne(largest, largest);  // all false
  std::size_t i = 0;
  for (; i + N <= P; i += N) {
    V x, yy, z, x0, y1, z0;
    hn::LoadInterleaved3(d, y + 3 * i, x, yy, z);
    hn::LoadInterleaved3(d, y0 + 3 * i, x0, y1, z0);
    const V dist = Norm2(hn::Sub(x, x0), hn::Sub(yy, y1), hn::Sub(z, z0));
    nan = hn::Or(nan, hn::IsNaN(dist));
    largest = hn::Max(largest, dist);
  }
  double best = hn::GetLane(hn::MaxOfLanes(d, largest));  // a maximum: exact in any order
  bool any_nan = !hn::AllFalse(d, nan);
  for (; i < P; ++i) {
    const double dist = Norm2(y[3 * i] - y0[3 * i], y[3 * i + 1] - y0[3 * i + 1], y[3 * i + 2] - y0[3 * i + 2]);
    any_nan = any_nan || std::isnan(dist);
    if (dist > best) best = dist;
  }
  out[0] = best;
  out[1] = any_nan ? 1.0 : 0.0;
}

void FinishStep(double* HWY_RESTRICT x, double* HWY_RESTRICT v, const double* HWY_RESTRICT dv, double h,
                std::size_t n) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V step = hn::Set(d, h);
  std::size_t k = 0;
  for (; k + N <= n; k += N) {
    const V vk = hn::Add(hn::LoadU(d, v + k), hn::LoadU(d, dv + k));
    hn::StoreU(vk, d, v + k);
    hn::StoreU(hn::Add(hn::LoadU(d, x + k), hn::Mul(step, vk)), d, x + k);
  }
  for (; k < n; ++k) {
    v[k] = v[k] + dv[k];
    x[k] = x[k] + h * v[k];
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(WeightedNorm2);
HWY_EXPORT(ImpulseNorm2);
HWY_EXPORT(GuessMisses);
HWY_EXPORT(MaxDistance2);
HWY_EXPORT(FinishStep);

double simd_weighted_norm2(const double* weight, const double* v, std::size_t B) {
  alignas(64) double sums[kPartialSums] = {};
  HWY_DYNAMIC_DISPATCH(WeightedNorm2)(weight, v, B, sums);
  return partial_sums_total(sums);
}

double simd_impulse_norm2(const double* mass, const double* dv, const double* r, std::size_t B) {
  alignas(64) double sums[kPartialSums] = {};
  HWY_DYNAMIC_DISPATCH(ImpulseNorm2)(mass, dv, r, B, sums);
  return partial_sums_total(sums);
}

void simd_guess_misses(const double* dv, const double* a, const double* b, const double* c, std::size_t n,
                       double miss[3]) {
  alignas(64) double sums[3 * kPartialSums] = {};
  if (!b) c = nullptr;
  HWY_DYNAMIC_DISPATCH(GuessMisses)(dv, a, b, c, n, sums);
  miss[0] = partial_sums_total(sums);
  if (b) miss[1] = partial_sums_total(sums + kPartialSums);
  if (c) miss[2] = partial_sums_total(sums + 2 * kPartialSums);
}

double simd_max_distance2(const double* y, const double* y0, std::size_t P) {
  double out[2];
  HWY_DYNAMIC_DISPATCH(MaxDistance2)(y, y0, P, out);
  return out[1] != 0.0 ? std::numeric_limits<double>::quiet_NaN() : out[0];
}

void simd_finish_step(double* x, double* v, const double* dv, double h, std::size_t n) {
  HWY_DYNAMIC_DISPATCH(FinishStep)(x, v, dv, h, n);
}

}  // namespace clothsim
#endif  // HWY_ONCE
