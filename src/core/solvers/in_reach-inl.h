// The SIMD form of for_each_penetration's reach test (step_problem.h), shared by the kernels
// that scan for contacts (contact_scan_kernels.cpp, vbd_grid_kernels.cpp). Highway's
// per-target header: each kernel includes it once per target, after <hwy/highway.h>.
#if defined(CLOTHSIM_SOLVERS_IN_REACH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CLOTHSIM_SOLVERS_IN_REACH_INL_H_
#undef CLOTHSIM_SOLVERS_IN_REACH_INL_H_
#else
#define CLOTHSIM_SOLVERS_IN_REACH_INL_H_
#endif

#include <hwy/highway.h>

#include <cmath>
#include <cstddef>

#include "core/solvers/step_problem.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {

// Lanes inside some collider's reach, with the scalar test's arithmetic
// (r = sqrt((dx^2 + dy^2) + dz^2)); a NaN distance enters, as there.
template <class D, class V = hwy::HWY_NAMESPACE::Vec<D>>
HWY_INLINE hwy::HWY_NAMESPACE::Mask<D> InReach(D d, const Colliders& c, V x, V y, V z) {
  namespace hn = hwy::HWY_NAMESPACE;
  auto inside = hn::Lt(y, hn::Set(d, c.ground ? c.ground_reach : -HUGE_VAL));
  for (std::size_t q = 0; q < c.centre.size(); ++q) {
    const V dx = hn::Sub(x, hn::Set(d, c.centre[q].x()));
    const V dy = hn::Sub(y, hn::Set(d, c.centre[q].y()));
    const V dz = hn::Sub(z, hn::Set(d, c.centre[q].z()));
    const V r = hn::Sqrt(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz)));
    inside = hn::Or(inside, hn::Not(hn::Ge(r, hn::Set(d, c.reach[q]))));
  }
  return inside;
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#endif  // include guard per target
