// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/pd_local_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

#include "pd_local_kernels.h"
#include "core/springs/spring_window-inl.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;

// scratch: 9 window arrays (y's components, then the sums at a and at b) of `stride` doubles.
void FamilyProjections(const SpringLayout& layout, const double* HWY_RESTRICT y,
                       const double* HWY_RESTRICT rest_by_slot, double h,
                       const std::int32_t* HWY_RESTRICT row, double* HWY_RESTRICT z,
                       double* HWY_RESTRICT scratch, std::size_t stride) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  double* in[3];
  double* plus[3];
  double* minus[3];
  for (std::size_t c = 0; c < 3; ++c)
    in[c] = scratch + c * stride, plus[c] = scratch + (3 + c) * stride, minus[c] = scratch + (6 + c) * stride;
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const auto copy_in = [&](std::size_t particle, std::size_t n, std::size_t at) {
    window::Deinterleave(y + 3 * particle, n, in[0] + at, in[1] + at, in[2] + at);
  };
  const auto body = [&](const SpringFamily& fam, std::size_t k0, std::size_t k1, std::size_t first) {
    const double* HWY_RESTRICT l0 = fam.rest.data();
    const double* HWY_RESTRICT blended = rest_by_slot + fam.slot_first;
    const std::size_t off = static_cast<std::size_t>(fam.offset);
    const auto k = hn::Set(d, fam.ks + fam.kd / h);
    for (std::size_t q = k0; q < k1; q += N) {
      const std::size_t a = first + q, b = a + off;
      const auto dx = hn::Sub(hn::LoadU(d, in[0] + a), hn::LoadU(d, in[0] + b));
      const auto dy = hn::Sub(hn::LoadU(d, in[1] + a), hn::LoadU(d, in[1] + b));
      const auto dz = hn::Sub(hn::LoadU(d, in[2] + a), hn::LoadU(d, in[2] + b));
      const auto l = window::Length(dx, dy, dz);
      const auto acts = hn::AndNot(hn::Le(l, zero), hn::Gt(hn::LoadU(d, l0 + q), zero));
      const auto scale = hn::IfThenElseZero(acts, hn::Mul(k, hn::Sub(hn::Div(hn::LoadU(d, blended + q), l), one)));
      const auto px = hn::Mul(scale, dx), py = hn::Mul(scale, dy), pz = hn::Mul(scale, dz);
      hn::StoreU(hn::Add(hn::LoadU(d, plus[0] + a), px), d, plus[0] + a);
      hn::StoreU(hn::Add(hn::LoadU(d, plus[1] + a), py), d, plus[1] + a);
      hn::StoreU(hn::Add(hn::LoadU(d, plus[2] + a), pz), d, plus[2] + a);
      hn::StoreU(hn::Sub(hn::LoadU(d, minus[0] + b), px), d, minus[0] + b);
      hn::StoreU(hn::Sub(hn::LoadU(d, minus[1] + b), py), d, minus[1] + b);
      hn::StoreU(hn::Sub(hn::LoadU(d, minus[2] + b), pz), d, minus[2] + b);
    }
  };
  const auto flush = [&](std::size_t particle, std::size_t n, std::size_t at) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t r = row[particle + i];
      if (r < 0) continue;
      for (std::size_t c = 0; c < 3; ++c) z[4 * r + c] += plus[c][at + i] + minus[c][at + i];
    }
  };
  window::WalkFamilies(layout, scratch, stride, 3, 6, copy_in, body, flush);
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(FamilyProjections);

void pd_family_projections(const SpringLayout& layout, const Eigen::Matrix3Xd& y,
                           const double* rest, double h, const std::int32_t* row, Eigen::Matrix4Xd& z) {
  thread_local hwy::AlignedFreeUniquePtr<double[]> scratch;
  thread_local std::size_t capacity = 0;
  const std::size_t stride = window_stride(layout);
  if (9 * stride > capacity) capacity = 9 * stride, scratch = hwy::AllocateAligned<double>(capacity);
  HWY_DYNAMIC_DISPATCH(FamilyProjections)(layout, y.data(), rest, h, row, z.data(), scratch.get(), stride);
}

}  // namespace clothsim
#endif  // HWY_ONCE
