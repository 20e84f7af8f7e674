// Fixed-order partial sums, shared by the SIMD passes that reduce (cg_kernels.cpp,
// newton_kernels.cpp, potential_kernels.cpp): entry (or body) k goes into sum k mod
// kPartialSums, and the sums are added in order at the end. Every Highway target's lane count
// divides kPartialSums and every vector starts at a multiple of its lane count, so each sum sees
// the same terms in the same order on every target: with no fused multiply-add (the files are
// compiled with -ffp-contract=off), every target gives the same bits.
//
// Highway's -inl.h pattern (as spring_window-inl.h): included once per target after
// foreach_target.h; the part above the toggle guard is ordinary C++, compiled once.
#ifndef CLOTHSIM_PARTIAL_SUMS_ONCE
#define CLOTHSIM_PARTIAL_SUMS_ONCE

#include <cstddef>

namespace clothsim {

inline constexpr std::size_t kPartialSums = 16;

// The sums' total, in a fixed order.
inline double partial_sums_total(const double* sums) {
  double out = 0.0;
  for (std::size_t j = 0; j < kPartialSums; ++j) out += sums[j];
  return out;
}

}  // namespace clothsim
#endif  // CLOTHSIM_PARTIAL_SUMS_ONCE

#if defined(CLOTHSIM_PARTIAL_SUMS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CLOTHSIM_PARTIAL_SUMS_INL_H_
#undef CLOTHSIM_PARTIAL_SUMS_INL_H_
#else
#define CLOTHSIM_PARTIAL_SUMS_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace partial_sums {
namespace hn = hwy::HWY_NAMESPACE;

static_assert(HWY_MAX_BYTES / sizeof(double) <= kPartialSums, "a vector's lanes are consecutive sums");

// sums[k mod kPartialSums ..] += value, for the lanes of a vector at entry k (k a multiple of
// the lane count).
template <class V>
HWY_INLINE void Accumulate(double* HWY_RESTRICT sums, std::size_t k, V value) {
  const hn::DFromV<V> d;
  const std::size_t j = k % kPartialSums;
  hn::StoreU(hn::Add(hn::LoadU(d, sums + j), value), d, sums + j);
}

}  // namespace partial_sums
}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#endif  // the toggle guard
