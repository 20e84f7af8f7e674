// The walk every SIMD pass over a SpringLayout's families shares (the force pass,
// spring_kernels.cpp; the implicit step's passes, integrators/potential_kernels.cpp): blocks
// of positions, every family within a block, and a window of structure-of-arrays scratch that
// slides with the blocks.
//
// Per block of kWindowBlock positions the walk copies in the particles the block reads (the
// caller's copy_in: x, v, y or p, deinterleaved), runs each family over its positions in the
// block (the caller's body: contiguous loads of p .. p+L-1 and p+offset .. p+offset+L-1, no
// gathers), then hands the particles it finished to the caller's flush (add the sums into f,
// write a diagonal block). A body adds what it finds at a spring's a into one set of sums and
// what it finds at its b into another, so no two lanes of a store share a particle, a pass never
// stores where its next load overlaps, and a particle's terms are summed in (block, family)
// order whatever the lane count: every Highway target gives the same bits. The window holds
// about kWindowBlock + 2 nx particles, so it stays in L1/L2 on any grid (at 256 x 256, scratch
// over the whole grid walked family after family ran the force pass at half this speed).
//
// Highway's -inl.h pattern: the file is included once per target after foreach_target.h (the
// toggle guard below), its per-target part in that target's namespace; the part above the
// toggle is ordinary C++, compiled once.
#ifndef CLOTHSIM_SPRING_WINDOW_ONCE
#define CLOTHSIM_SPRING_WINDOW_ONCE

#include <algorithm>
#include <cstddef>

#include "spring_kernels.h"  // sticky_max
#include "spring_layout.h"

namespace clothsim {

// Positions per block (a multiple of kSpringLanePad, so of every target's lane count): small
// enough that a block's window stays in L2 (BENCHMARKS.md, "Spring force pass", has the sizes tried).
inline constexpr std::size_t kWindowBlock = 2048;

// How many particles a window holds: a block's positions, the farthest b = first + offset
// past them, and a vector's worth of lanes.
inline std::size_t window_of(const SpringLayout& layout) {
  std::size_t reach = 0;
  for (const SpringFamily& fam : layout.families)
    reach = std::max(reach, static_cast<std::size_t>(fam.first) + static_cast<std::size_t>(fam.offset));
  return kWindowBlock + reach + kSpringLanePad;
}

// The length of one window array, rounded up so that every array starts 64-byte aligned.
inline std::size_t window_stride(const SpringLayout& layout) { return (window_of(layout) + 7) / 8 * 8; }

}  // namespace clothsim
#endif  // CLOTHSIM_SPRING_WINDOW_ONCE

#if defined(CLOTHSIM_SPRING_WINDOW_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CLOTHSIM_SPRING_WINDOW_INL_H_
#undef CLOTHSIM_SPRING_WINDOW_INL_H_
#else
#define CLOTHSIM_SPRING_WINDOW_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace window {
namespace hn = hwy::HWY_NAMESPACE;

// n particles of interleaved xyz (3 x n) -> three arrays of n.
HWY_INLINE void Deinterleave(const double* HWY_RESTRICT in, std::size_t n, double* HWY_RESTRICT xs,
                             double* HWY_RESTRICT ys, double* HWY_RESTRICT zs) {
  const hn::ScalableTag<double> d;
  const std::size_t N = hn::Lanes(d);
  std::size_t p = 0;
  for (; p + N <= n; p += N) {
    hn::Vec<decltype(d)> X, Y, Z;
    hn::LoadInterleaved3(d, in + 3 * p, X, Y, Z);
    hn::StoreU(X, d, xs + p);
    hn::StoreU(Y, d, ys + p);
    hn::StoreU(Z, d, zs + p);
  }
  for (; p < n; ++p) {
    xs[p] = in[3 * p];
    ys[p] = in[3 * p + 1];
    zs[p] = in[3 * p + 2];
  }
}

// n particles of out (3 x n, interleaved) += a + b per component (a, b: three arrays each).
HWY_INLINE void AddInterleaved(const double* const* HWY_RESTRICT a, const double* const* HWY_RESTRICT b,
                               std::size_t n, double* HWY_RESTRICT out) {
  const hn::ScalableTag<double> d;
  const std::size_t N = hn::Lanes(d);
  std::size_t p = 0;
  for (; p + N <= n; p += N) {
    hn::Vec<decltype(d)> X, Y, Z;
    hn::LoadInterleaved3(d, out + 3 * p, X, Y, Z);
    X = hn::Add(X, hn::Add(hn::LoadU(d, a[0] + p), hn::LoadU(d, b[0] + p)));
    Y = hn::Add(Y, hn::Add(hn::LoadU(d, a[1] + p), hn::LoadU(d, b[1] + p)));
    Z = hn::Add(Z, hn::Add(hn::LoadU(d, a[2] + p), hn::LoadU(d, b[2] + p)));
    hn::StoreInterleaved3(X, Y, Z, d, out + 3 * p);
  }
  for (; p < n; ++p)
    for (int c = 0; c < 3; ++c) out[3 * p + c] += a[c][p] + b[c][p];
}

// The walk. scratch: `inputs` then `sums` arrays of `stride` >= window_of(layout) doubles,
// array i at scratch + i stride, each holding particles base .. base + stride - 1 of the
// current window at 0 .. stride - 1. The caller's functions, with window indices `at`:
//   copy_in(particle, n, at)   fill the input arrays with particles [particle, particle + n)
//                              (all below P; the walk zeroes the inputs past P and the sums);
//   body(fam, k0, k1, first)   run family fam over positions [k0, k1) (its springs join
//                              window indices first + k and first + k + fam.offset; a vector
//                              may read up to kSpringLanePad past k1, which holds zeros);
//   flush(particle, n, at)     particles [particle, particle + n) are finished: every spring
//                              that reaches them has been run.
// Returns how many particles were flushed (0 .. F): particles F .. P - 1 no spring reaches.
template <class CopyIn, class Body, class Flush>
HWY_INLINE std::size_t WalkFamilies(const SpringLayout& layout, double* HWY_RESTRICT scratch,
                             std::size_t stride, std::size_t inputs, std::size_t sums,
                             const CopyIn& copy_in, const Body& body, const Flush& flush) {
  const std::size_t P = static_cast<std::size_t>(layout.num_particles);
  const std::size_t arrays = inputs + sums;
  std::size_t longest = 0;  // positions in the longest family
  for (const SpringFamily& fam : layout.families)
    longest = std::max(longest, static_cast<std::size_t>(fam.count));
  const std::size_t window = window_of(layout);
  std::size_t base = 0;     // the window's first particle
  std::size_t copied = 0;   // below this particle: inputs in the window, sums started
  std::size_t flushed = 0;  // the particles below this one are flushed
  // Readies particles [copied, to) (to <= base + window): inputs copied, sums zero.
  const auto copy_up_to = [&](std::size_t to) {
    if (to <= copied) return;
    const std::size_t upto = std::min(to, P), from = copied - base, end = to - base;
    if (copied < upto) copy_in(copied, upto - copied, from);
    const std::size_t past = std::max(copied, upto) - base;  // zeros past P
    for (std::size_t i = 0; i < inputs; ++i) std::fill(scratch + i * stride + past, scratch + i * stride + end, 0.0);
    for (std::size_t i = inputs; i < arrays; ++i) std::fill(scratch + i * stride + from, scratch + i * stride + end, 0.0);
    copied = to;
  };
  const auto flush_up_to = [&](std::size_t to) {
    if (to <= flushed) return;
    flush(flushed, to - flushed, flushed - base);
    flushed = to;
  };
  for (std::size_t k0 = 0; k0 < longest; k0 += kWindowBlock) {
    if (k0 > base) {  // slide: particles k0 .. copied - 1 to the front
      for (std::size_t i = 0; i < arrays; ++i) {
        double* a = scratch + i * stride;
        std::copy(a + (k0 - base), a + (copied - base), a);
      }
      base = k0;
    }
    copy_up_to(std::min(k0 + window, P + kSpringLanePad));  // all this block reads or writes
    for (const SpringFamily& fam : layout.families) {
      const std::size_t count = static_cast<std::size_t>(fam.count);
      if (k0 >= count) continue;
      const std::size_t first = static_cast<std::size_t>(fam.first) - base;  // k >= base: no wrap
      body(fam, k0, std::min(k0 + kWindowBlock, count), first);
    }
    // Particles below k0 + kWindowBlock are finished: every spring at p has its a <= p.
    flush_up_to(std::min(k0 + kWindowBlock, P));
  }
  flush_up_to(std::min(copied, P));  // the rest of the particles any spring reached
  return flushed;
}

// A spring's length from its ends' differences, summed as the scalar passes sum it.
template <class V>
HWY_INLINE V Length(V dx, V dy, V dz) {
  return hn::Sqrt(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz)));
}

// Each lane's largest l / l0 so far, over the lanes where `spring` is set: l / l0 can exceed
// the lane's ratio only if l >= ratio l0 (rounding is monotone), so the division runs only
// then, and the result is the exact maximum of the rounded quotients whatever the order; a NaN
// length always enters and sticks. Every pass that reports strain keeps it so.
template <class D, class V, class M>
HWY_INLINE V GrowRatio(D d, V ratio, V l, V l0, M spring) {
  const V zero = hn::Zero(d);
  const M grows = hn::And(
      spring, hn::Or(hn::And(hn::Gt(l, zero), hn::Ge(l, hn::Mul(ratio, l0))), hn::IsNaN(l)));
  if (hn::AllFalse(d, grows)) return ratio;
  const V q = hn::Div(l, l0);
  return hn::IfThenElse(hn::AndNot(hn::Le(q, ratio), grows), q, ratio);
}

// The largest of GrowRatio's lanes (at least 1), a NaN winning.
template <class D, class V>
HWY_INLINE double WorstRatio(D d, V ratio) {
  double lanes[kSpringLanePad];
  hn::StoreU(ratio, d, lanes);
  double worst = 1.0;
  for (std::size_t i = 0; i < hn::Lanes(d); ++i) worst = sticky_max(worst, lanes[i]);
  return worst;
}

}  // namespace window
}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#endif  // the toggle guard
