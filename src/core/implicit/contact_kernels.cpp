// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick one at
// run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/implicit/contact_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "contact_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

void Screen(const NearScreen& screen, const double* HWY_RESTRICT x, const double* HWY_RESTRICT v,
            const double* HWY_RESTRICT g, double h, std::size_t n, std::vector<std::int32_t>& out) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V hv = hn::Set(d, h);
  const V ground = hn::Set(d, screen.ground);
  HWY_ALIGN double tail[3 * 3 * 16] = {};
  HWY_ALIGN double near[16];
  for (std::size_t p = 0; p < n; p += N) {
    const std::size_t lanes = std::min(N, n - p);
    const double *xp = x + 3 * p, *vp = v ? v + 3 * p : nullptr, *gp = g ? g + 3 * p : nullptr;
    if (lanes < N) {  // the last particles, from a padded copy (its extra lanes are ignored)
      std::copy(xp, xp + 3 * lanes, tail);
      xp = tail;
      if (vp) std::copy(vp, vp + 3 * lanes, tail + 3 * N), vp = tail + 3 * N;
      if (gp) std::copy(gp, gp + 3 * lanes, tail + 6 * N), gp = tail + 6 * N;
    }
    V X, Y, Z;
    hn::LoadInterleaved3(d, xp, X, Y, Z);
    if (vp) {  // at = x + h (v + g), as the exact search computes it
      V VX, VY, VZ;
      hn::LoadInterleaved3(d, vp, VX, VY, VZ);
      if (gp) {
        V GX, GY, GZ;
        hn::LoadInterleaved3(d, gp, GX, GY, GZ);
        VX = hn::Add(VX, GX), VY = hn::Add(VY, GY), VZ = hn::Add(VZ, GZ);
      }
      X = hn::Add(X, hn::Mul(hv, VX)), Y = hn::Add(Y, hn::Mul(hv, VY)), Z = hn::Add(Z, hn::Mul(hv, VZ));
    }
    auto hit = hn::Lt(Y, ground);
    for (std::size_t s = 0; s < screen.spheres; ++s) {
      const V dx = hn::Sub(X, hn::Set(d, screen.centre[3 * s]));
      const V dy = hn::Sub(Y, hn::Set(d, screen.centre[3 * s + 1]));
      const V dz = hn::Sub(Z, hn::Set(d, screen.centre[3 * s + 2]));
      const V d2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
      hit = hn::Or(hit, hn::Lt(d2, hn::Set(d, screen.bound2[s])));
    }
    if (hn::AllFalse(d, hit)) continue;  // most vectors: no particle near anything
    hn::Store(hn::IfThenElseZero(hit, hn::Set(d, 1.0)), d, near);
    for (std::size_t j = 0; j < lanes; ++j)
      if (near[j] != 0.0) out.push_back(static_cast<std::int32_t>(p + j));
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(Screen);

void near_screen(const NearScreen& screen, const double* x, const double* v, const double* g,
                 double h, std::size_t n, std::vector<std::int32_t>& near) {
  near.clear();
  HWY_DYNAMIC_DISPATCH(Screen)(screen, x, v, g, h, n, near);
}

}  // namespace clothsim
#endif  // HWY_ONCE
