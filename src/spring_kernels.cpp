// Highway's foreach_target.h compiles this file once per x86 target (Highway 1.0's: SCALAR for
// plain x86-64, SSSE3, SSE4, AVX2, AVX3 = AVX-512), each copy inside its own namespace;
// HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick the copy at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "spring_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

#include "spring_kernels.h"

#ifndef CLOTHSIM_SPRING_KERNELS_ONCE  // this part once, not once per target
#define CLOTHSIM_SPRING_KERNELS_ONCE
namespace clothsim {
namespace {

// Positions per block (a multiple of kSpringLanePad, so of every target's lane count); 2048
// ran 3-4 % faster than 1024 and 4096 at 256 x 256, its window (12 arrays of 2048 + 2 nx + 16
// doubles, 250 kB there) well inside L2.
constexpr std::size_t kBlock = 2048;

// How far past a block's first position the block reads and writes: its kBlock positions,
// the farthest b = first + offset past them, and a vector's worth of lanes.
std::size_t window_of(const SpringLayout& layout) {
  std::size_t reach = 0;
  for (const SpringFamily& fam : layout.families)
    reach = std::max(reach, static_cast<std::size_t>(fam.first) + static_cast<std::size_t>(fam.offset));
  return kBlock + reach + kSpringLanePad;
}

}  // namespace
}  // namespace clothsim
#endif

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
static_assert(HWY_MAX_BYTES / sizeof(double) <= kSpringLanePad, "the layout's padding is a vector");

// n particles of interleaved xyz (3 x n) -> three arrays of n.
void Deinterleave(const double* HWY_RESTRICT in, std::size_t n, double* HWY_RESTRICT xs,
                  double* HWY_RESTRICT ys, double* HWY_RESTRICT zs) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t p = 0;
  for (; p + N <= n; p += N) {
    hn::Vec<D> X, Y, Z;
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

// n particles of out (3 x n, interleaved) += a + b, per component (a, b: arrays of n).
void AddInterleaved(const double* HWY_RESTRICT ax, const double* HWY_RESTRICT ay,
                    const double* HWY_RESTRICT az, const double* HWY_RESTRICT bx,
                    const double* HWY_RESTRICT by, const double* HWY_RESTRICT bz, std::size_t n,
                    double* HWY_RESTRICT out) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t p = 0;
  for (; p + N <= n; p += N) {
    hn::Vec<D> X, Y, Z;
    hn::LoadInterleaved3(d, out + 3 * p, X, Y, Z);
    X = hn::Add(X, hn::Add(hn::LoadU(d, ax + p), hn::LoadU(d, bx + p)));
    Y = hn::Add(Y, hn::Add(hn::LoadU(d, ay + p), hn::LoadU(d, by + p)));
    Z = hn::Add(Z, hn::Add(hn::LoadU(d, az + p), hn::LoadU(d, bz + p)));
    hn::StoreInterleaved3(X, Y, Z, d, out + 3 * p);
  }
  for (; p < n; ++p) {
    out[3 * p] += ax[p] + bx[p];
    out[3 * p + 1] += ay[p] + by[p];
    out[3 * p + 2] += az[p] + bz[p];
  }
}

// The families' forces into f; `scratch` holds 12 arrays of `stride` >= window_of(layout)
// doubles (x, v, and the two force accumulators, each as three components). Returns the
// largest l / l0.
//
// The positions are walked in blocks of kBlock, every family in turn within a block. The
// scratch is a window over the particles that slides with the blocks: a block copies in the
// particles it reads just before it runs and adds its finished particles into f just after,
// and the particles it shares with the next block move to the window's front. So the scratch
// stays in L1/L2 whatever the grid (at 256 x 256, scratch arrays over the whole grid, twice
// L2, walked family after family with the copy and the add as passes of their own, ran at half
// this speed). A particle's forces are summed in (block, family) order: fixed, whatever the
// lane count.
double FamilySpringForces(const SpringLayout& layout, const double* HWY_RESTRICT x,
                          const double* HWY_RESTRICT v, double* HWY_RESTRICT f,
                          double* HWY_RESTRICT scratch, std::size_t stride) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const std::size_t P = static_cast<std::size_t>(layout.num_particles);
  // Each array holds particles base .. base + stride - 1 at 0 .. stride - 1 (zeros past P).
  double* HWY_RESTRICT xs = scratch;
  double* HWY_RESTRICT ys = xs + stride;
  double* HWY_RESTRICT zs = ys + stride;
  double* HWY_RESTRICT vxs = zs + stride;
  double* HWY_RESTRICT vys = vxs + stride;
  double* HWY_RESTRICT vzs = vys + stride;
  double* HWY_RESTRICT fpx = vzs + stride;  // + the force on each spring's a, at a
  double* HWY_RESTRICT fpy = fpx + stride;
  double* HWY_RESTRICT fpz = fpy + stride;
  double* HWY_RESTRICT fmx = fpz + stride;  // - the force on each spring's a, at its b
  double* HWY_RESTRICT fmy = fmx + stride;
  double* HWY_RESTRICT fmz = fmy + stride;
  double* const inputs[] = {xs, ys, zs, vxs, vys, vzs};
  double* const sums[] = {fpx, fpy, fpz, fmx, fmy, fmz};

  std::size_t longest = 0;  // positions in the longest family
  for (const SpringFamily& fam : layout.families) longest = std::max(longest, static_cast<std::size_t>(fam.count));
  const std::size_t window = window_of(layout);
  std::size_t base = 0;     // the window's first particle
  std::size_t copied = 0;   // below this particle: x and v in the window, sums started
  std::size_t flushed = 0;  // f holds the forces of the particles below this one
  // Readies particles [copied, to) (to <= base + window): x and v copied, both sums zero.
  const auto copy_up_to = [&](std::size_t to) {
    if (to <= copied) return;
    const std::size_t in = std::min(to, P), from = copied - base, end = to - base;
    if (copied < in) {
      Deinterleave(x + 3 * copied, in - copied, xs + from, ys + from, zs + from);
      Deinterleave(v + 3 * copied, in - copied, vxs + from, vys + from, vzs + from);
    }
    const std::size_t past = std::max(copied, in) - base;  // zeros past P
    for (double* a : inputs) std::fill(a + past, a + end, 0.0);
    for (double* a : sums) std::fill(a + from, a + end, 0.0);
    copied = to;
  };
  // Adds the finished particles [flushed, to) into f.
  const auto flush_up_to = [&](std::size_t to) {
    if (to <= flushed) return;
    const std::size_t from = flushed - base;
    AddInterleaved(fpx + from, fpy + from, fpz + from, fmx + from, fmy + from, fmz + from,
                   to - flushed, f + 3 * flushed);
    flushed = to;
  };

  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0);
  auto ratio = one;  // per lane: the largest l / l0 so far
  for (std::size_t k0 = 0; k0 < longest; k0 += kBlock) {
    if (k0 > base) {  // slide: particles k0 .. copied - 1 to the front
      for (double* a : inputs) std::copy(a + (k0 - base), a + (copied - base), a);
      for (double* a : sums) std::copy(a + (k0 - base), a + (copied - base), a);
      base = k0;
    }
    copy_up_to(std::min(k0 + window, P + kSpringLanePad));  // all this block reads or writes
    for (const SpringFamily& fam : layout.families) {
      const std::size_t count = static_cast<std::size_t>(fam.count);
      if (k0 >= count) continue;
      const double* HWY_RESTRICT rest = fam.rest.data();
      const std::size_t first = static_cast<std::size_t>(fam.first) - base;  // in the window
      const std::size_t off = static_cast<std::size_t>(fam.offset);
      const auto minus_ks = hn::Set(d, -fam.ks);
      const auto kd = hn::Set(d, fam.kd);
      // The family's last vector may run past `count` (rest is padded with zeros: no spring)
      // and past P (zeros in the window): those lanes are masked out below.
      const std::size_t k1 = std::min(k0 + kBlock, count);
      for (std::size_t k = k0; k < k1; k += N) {
        const std::size_t a = first + k, b = a + off;  // window indices (k >= base: no wrap)
        HWY_DASSERT(b + N <= stride);  // debug builds: the window holds what the block touches
        const auto l0 = hn::LoadU(d, rest + k);
        const auto dx = hn::Sub(hn::LoadU(d, xs + a), hn::LoadU(d, xs + b));
        const auto dy = hn::Sub(hn::LoadU(d, ys + a), hn::LoadU(d, ys + b));
        const auto dz = hn::Sub(hn::LoadU(d, zs + a), hn::LoadU(d, zs + b));
        const auto l = hn::Sqrt(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz)));
        const auto inv_l = hn::Div(one, l);
        const auto ux = hn::Mul(dx, inv_l), uy = hn::Mul(dy, inv_l), uz = hn::Mul(dz, inv_l);
        const auto vrel = hn::Add(
            hn::Add(hn::Mul(hn::Sub(hn::LoadU(d, vxs + a), hn::LoadU(d, vxs + b)), ux),
                    hn::Mul(hn::Sub(hn::LoadU(d, vys + a), hn::LoadU(d, vys + b)), uy)),
            hn::Mul(hn::Sub(hn::LoadU(d, vzs + a), hn::LoadU(d, vzs + b)), uz));
        // f_a = (-ks (l - l0) - kd (vr . u)) u, f_b = -f_a (the seed's formula, as the scalar pass).
        const auto mag = hn::Sub(hn::Mul(minus_ks, hn::Sub(l, l0)), hn::Mul(kd, vrel));
        const auto spring = hn::Gt(l0, zero);                  // a spring at this position
        const auto acts = hn::AndNot(hn::Le(l, zero), spring);  // and its ends apart (or NaN)
        const auto fx = hn::IfThenElseZero(acts, hn::Mul(mag, ux));
        const auto fy = hn::IfThenElseZero(acts, hn::Mul(mag, uy));
        const auto fz = hn::IfThenElseZero(acts, hn::Mul(mag, uz));
        hn::StoreU(hn::Add(hn::LoadU(d, fpx + a), fx), d, fpx + a);
        hn::StoreU(hn::Add(hn::LoadU(d, fpy + a), fy), d, fpy + a);
        hn::StoreU(hn::Add(hn::LoadU(d, fpz + a), fz), d, fpz + a);
        hn::StoreU(hn::Sub(hn::LoadU(d, fmx + b), fx), d, fmx + b);
        hn::StoreU(hn::Sub(hn::LoadU(d, fmy + b), fy), d, fmy + b);
        hn::StoreU(hn::Sub(hn::LoadU(d, fmz + b), fz), d, fmz + b);

        // Strain: l / l0 can exceed the lane's ratio only if l >= ratio l0 (rounding is
        // monotone), so the division runs only then; a NaN length always enters and sticks.
        const auto grows = hn::And(
            spring, hn::Or(hn::And(hn::Gt(l, zero), hn::Ge(l, hn::Mul(ratio, l0))), hn::IsNaN(l)));
        if (!hn::AllFalse(d, grows)) {
          const auto q = hn::Div(l, l0);
          ratio = hn::IfThenElse(hn::AndNot(hn::Le(q, ratio), grows), q, ratio);
        }
      }
    }
    // Particles below k0 + kBlock are finished: every spring at p has its a <= p, so k <= p.
    flush_up_to(std::min(k0 + kBlock, P));
  }
  flush_up_to(std::min(copied, P));  // the rest of the particles any spring reached

  double lanes[kSpringLanePad];
  hn::StoreU(ratio, d, lanes);
  double out = 1.0;
  for (std::size_t i = 0; i < N; ++i) out = sticky_max(out, lanes[i]);
  return out;
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(FamilySpringForces);
HWY_EXPORT(TargetName);

double accumulate_family_spring_forces(const SpringLayout& layout, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  // Scratch per thread (compare runs lanes on threads), grown, never shrunk: a window of
  // about kBlock + 2 nx particles, not the whole grid.
  thread_local hwy::AlignedFreeUniquePtr<double[]> scratch;
  thread_local std::size_t capacity = 0;
  const std::size_t stride = (window_of(layout) + 7) / 8 * 8;  // arrays 64-byte aligned
  if (12 * stride > capacity) {
    capacity = 12 * stride;
    scratch = hwy::AllocateAligned<double>(capacity);
  }
  return HWY_DYNAMIC_DISPATCH(FamilySpringForces)(layout, x.data(), v.data(), f.data(),
                                                  scratch.get(), stride);
}

const char* spring_kernel_target() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace clothsim
#endif  // HWY_ONCE
