// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/contact_scan_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "contact_scan_kernels.h"
#include "in_reach-inl.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

HWY_INLINE void Collect(const D d, hn::Mask<D> inside, std::size_t first, std::size_t n,
                        std::vector<std::int32_t>& out) {
  if (hn::AllFalse(d, inside)) return;
  double lanes[HWY_MAX_BYTES / sizeof(double)];
  hn::StoreU(hn::IfThenElseZero(inside, hn::Set(d, 1.0)), d, lanes);
  for (std::size_t k = 0; k < hn::Lanes(d) && first + k < n; ++k)
    if (lanes[k] != 0.0) out.push_back(static_cast<std::int32_t>(first + k));
}

void ScanSoa(const Colliders& c, const double* HWY_RESTRICT y, std::size_t stride, std::size_t n,
             std::vector<std::int32_t>& out) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t i = 0;
  for (; i + N <= n; i += N)
    Collect(d, InReach(d, c, hn::LoadU(d, y + i), hn::LoadU(d, y + stride + i), hn::LoadU(d, y + 2 * stride + i)), i, n, out);
  for (; i < n; ++i) {
    const auto one = InReach(d, c, hn::Set(d, y[i]), hn::Set(d, y[stride + i]), hn::Set(d, y[2 * stride + i]));
    if (!hn::AllFalse(d, one)) out.push_back(static_cast<std::int32_t>(i));
  }
}

void ScanColumns(const Colliders& c, const double* HWY_RESTRICT y, std::size_t n, std::vector<std::int32_t>& out) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t i = 0;
  for (; i + N <= n; i += N) {
    V x0, x1, x2;
    hn::LoadInterleaved3(d, y + 3 * i, x0, x1, x2);
    Collect(d, InReach(d, c, x0, x1, x2), i, n, out);
  }
  for (; i < n; ++i) {
    const auto one = InReach(d, c, hn::Set(d, y[3 * i]), hn::Set(d, y[3 * i + 1]), hn::Set(d, y[3 * i + 2]));
    if (!hn::AllFalse(d, one)) out.push_back(static_cast<std::int32_t>(i));
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(ScanSoa);
HWY_EXPORT(ScanColumns);

void particles_in_reach(const Colliders& c, const double* y, std::size_t stride, std::size_t n,
                        std::vector<std::int32_t>& inside) {
  inside.clear();
  HWY_DYNAMIC_DISPATCH(ScanSoa)(c, y, stride, n, inside);
}

void particles_in_reach(const Colliders& c, const Eigen::Matrix3Xd& y, std::size_t n,
                        std::vector<std::int32_t>& inside) {
  inside.clear();
  HWY_DYNAMIC_DISPATCH(ScanColumns)(c, y.data(), n, inside);
}

}  // namespace clothsim
#endif  // HWY_ONCE
