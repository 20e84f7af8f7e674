// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick one at
// run time. The walk over blocks and the sliding window are spring_window-inl.h's, shared with
// the force pass (spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/implicit/potential_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "potential_kernels.h"
#include "core/linear/partial_sums-inl.h"

#include "core/springs/spring_window-inl.h"  // the walk over the families: its window and helpers

#ifndef CLOTHSIM_POTENTIAL_KERNELS_ONCE  // this part once, not once per target
#define CLOTHSIM_POTENTIAL_KERNELS_ONCE
namespace clothsim {
namespace {

// Phi's partial sums (partial_sums-inl.h): position k goes to sum k mod kSums, so a vector's
// lanes are consecutive sums and each sum sees the same springs in the same order on every target.
constexpr std::size_t kSums = kPartialSums;
// Window arrays, at most: 3 inputs (x, y or p) and 6 sums (at a, at b; 3 components each).
constexpr std::size_t kArrays = 9;

}  // namespace
}  // namespace clothsim
#endif

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;
static_assert(HWY_MAX_BYTES / sizeof(double) <= kSpringLanePad, "the layout's padding is a vector");

namespace {

// A vector of doubles from doubles, or from floats widened exactly (the mat-vec's float copy,
// SpringBlockMatrix::single).
HWY_INLINE V LoadAsDouble(D d, const double* HWY_RESTRICT p) { return hn::LoadU(d, p); }
HWY_INLINE V LoadAsDouble(D d, const float* HWY_RESTRICT p) { return hn::PromoteTo(d, hn::LoadU(hn::Rebind<float, D>(), p)); }

// The window of a pass over an interleaved 3 x P input (x, y or p): its components, and
// (when the pass has an output) the two sums, three components each.
struct Window {
  double* in[3];     // x, y or p
  double* plus[3];   // contributions at each spring's a
  double* minus[3];  // contributions at each spring's b
  Window(double* scratch, std::size_t stride) {
    for (int c = 0; c < 3; ++c) {
      in[c] = scratch + c * stride;
      plus[c] = scratch + (3 + c) * stride;
      minus[c] = scratch + (6 + c) * stride;
    }
  }
};

// at[k], at[k + stride], at[k + 2 stride] (one vector each: a window sum's x, y and z) += v0, v1, v2.
HWY_INLINE void AddComponents(double* HWY_RESTRICT at, std::size_t k, std::size_t stride, V v0, V v1, V v2) {
  const D d;
  hn::StoreU(hn::Add(hn::LoadU(d, at + k), v0), d, at + k);
  hn::StoreU(hn::Add(hn::LoadU(d, at + stride + k), v1), d, at + stride + k);
  hn::StoreU(hn::Add(hn::LoadU(d, at + 2 * stride + k), v2), d, at + 2 * stride + k);
}

// A family's positions k0 .. k0 + n - 1 in a window block: the first one's slot s, and the
// window indices a and b of its spring's ends (the others follow at +1 each).
struct Range {
  std::size_t k0, n, s, a, b;
};

// Walks the families (spring_window-inl.h) with `in` (3 x P) copied into the window; calls
// run(fam, range) for each family's positions in a block; with `out`, adds the finished particles'
// sums into it, or, with `diag` (3x3 symmetric blocks as SpringBlockMatrix::diag_soa, of B
// bodies, in double or float), writes diag_i in_i + the sums there. Returns how many particles
// it finished. A hot loop over a range belongs in a function taking its pointers as restrict
// parameters (RunSingle): Highway's stores may alias anything, so a loop that reads its
// pointers through a capture reloads them after every store.
template <class Run, class T = double>
std::size_t WalkRanges(const SpringLayout& layout, const double* HWY_RESTRICT in, double* HWY_RESTRICT out,
                       double* HWY_RESTRICT scratch, std::size_t stride, const Window& w, const Run& run,
                       const T* HWY_RESTRICT diag = nullptr, std::size_t bodies = 0) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const auto copy_in = [&](std::size_t particle, std::size_t n, std::size_t at) {
    window::Deinterleave(in + 3 * particle, n, w.in[0] + at, w.in[1] + at, w.in[2] + at);
  };
  const auto ranges = [&](const SpringFamily& fam, std::size_t k0, std::size_t k1, std::size_t first) {
    const std::size_t a = first + k0;
    run(fam, Range{k0, k1 - k0, fam.slot_first + k0, a, a + static_cast<std::size_t>(fam.offset)});
  };
  const auto flush = [&](std::size_t particle, std::size_t n, std::size_t at) {
    if (!out) return;
    if (!diag) {
      const double* const plus[] = {w.plus[0] + at, w.plus[1] + at, w.plus[2] + at};
      const double* const minus[] = {w.minus[0] + at, w.minus[1] + at, w.minus[2] + at};
      window::AddInterleaved(plus, minus, n, out + 3 * particle);
      return;
    }
    // out_i = D_i p_i + (plus + minus): sparse_system.cpp's multiply_diagonal, then the sums,
    // with the same operations in the same order.
    const T* HWY_RESTRICT dxx = diag + particle;
    const T* HWY_RESTRICT dyy = dxx + bodies;
    const T* HWY_RESTRICT dzz = dyy + bodies;
    const T* HWY_RESTRICT dxy = dzz + bodies;
    const T* HWY_RESTRICT dxz = dxy + bodies;
    const T* HWY_RESTRICT dyz = dxz + bodies;
    const double *p0 = w.in[0] + at, *p1 = w.in[1] + at, *p2 = w.in[2] + at;
    const double *a0 = w.plus[0] + at, *a1 = w.plus[1] + at, *a2 = w.plus[2] + at;
    const double *b0 = w.minus[0] + at, *b1 = w.minus[1] + at, *b2 = w.minus[2] + at;
    double* HWY_RESTRICT y = out + 3 * particle;
    std::size_t i = 0;
    for (; i + N <= n; i += N) {
      const V xx = LoadAsDouble(d, dxx + i), yy = LoadAsDouble(d, dyy + i), zz = LoadAsDouble(d, dzz + i);
      const V xy = LoadAsDouble(d, dxy + i), xz = LoadAsDouble(d, dxz + i), yz = LoadAsDouble(d, dyz + i);
      const V q0 = hn::LoadU(d, p0 + i), q1 = hn::LoadU(d, p1 + i), q2 = hn::LoadU(d, p2 + i);
      const V y0 = hn::Add(hn::Add(hn::Mul(xx, q0), hn::Mul(xy, q1)), hn::Mul(xz, q2));
      const V y1 = hn::Add(hn::Add(hn::Mul(xy, q0), hn::Mul(yy, q1)), hn::Mul(yz, q2));
      const V y2 = hn::Add(hn::Add(hn::Mul(xz, q0), hn::Mul(yz, q1)), hn::Mul(zz, q2));
      hn::StoreInterleaved3(hn::Add(y0, hn::Add(hn::LoadU(d, a0 + i), hn::LoadU(d, b0 + i))),
                            hn::Add(y1, hn::Add(hn::LoadU(d, a1 + i), hn::LoadU(d, b1 + i))),
                            hn::Add(y2, hn::Add(hn::LoadU(d, a2 + i), hn::LoadU(d, b2 + i))), d, y + 3 * i);
    }
    for (; i < n; ++i) {
      const double xx = dxx[i], yy = dyy[i], zz = dzz[i], xy = dxy[i], xz = dxz[i], yz = dyz[i];
      y[3 * i] = (xx * p0[i] + xy * p1[i] + xz * p2[i]) + (a0[i] + b0[i]);
      y[3 * i + 1] = (xy * p0[i] + yy * p1[i] + yz * p2[i]) + (a1[i] + b1[i]);
      y[3 * i + 2] = (xz * p0[i] + yz * p1[i] + zz * p2[i]) + (a2[i] + b2[i]);
    }
  };
  return window::WalkFamilies(layout, scratch, stride, 3, out ? 6 : 0, copy_in, ranges, flush);
}

// WalkRanges without an output, with body(fam, k, a, b, w) called for each vector of
// positions k .. k+N-1 (a, b: window indices of its springs' ends): for a pass run once a step.
template <class Body>
void Walk(const SpringLayout& layout, const double* HWY_RESTRICT in, double* HWY_RESTRICT scratch,
          std::size_t stride, const Window& w, const Body& body) {
  const std::size_t N = hn::Lanes(D());
  const auto run = [&](const SpringFamily& fam, const Range& r) {
    for (std::size_t j = 0; j < r.n; j += N) {
      HWY_DASSERT(r.b + j + N <= stride);
      body(fam, r.k0 + j, r.a + j, r.b + j, w);
    }
  };
  WalkRanges(layout, in, nullptr, scratch, stride, w, run);
}

}  // namespace

// Start-of-step lengths by slot, and the largest l / l0 (as FamilySpringForces).
double FamilyLengths(const SpringLayout& layout, const double* HWY_RESTRICT x,
                     double* HWY_RESTRICT length, double* HWY_RESTRICT scratch, std::size_t stride) {
  const D d;
  const V zero = hn::Zero(d);
  V ratio = hn::Set(d, 1.0);
  Walk(layout, x, scratch, stride, Window(scratch, stride),
       [&](const SpringFamily& fam, std::size_t k, std::size_t a, std::size_t b, const Window& w) {
         const V l0 = hn::LoadU(d, fam.rest.data() + k);
         const V l = window::Length(hn::Sub(hn::LoadU(d, w.in[0] + a), hn::LoadU(d, w.in[0] + b)),
                            hn::Sub(hn::LoadU(d, w.in[1] + a), hn::LoadU(d, w.in[1] + b)),
                            hn::Sub(hn::LoadU(d, w.in[2] + a), hn::LoadU(d, w.in[2] + b)));
         const M spring = hn::Gt(l0, zero);
         hn::StoreU(hn::IfThenElseZero(spring, l), d, length + fam.slot_first + k);
         ratio = window::GrowRatio(d, ratio, l, l0, spring);
       });
  return window::WorstRatio(d, ratio);
}

// The largest l / l0 of lengths already by slot (FamilyLengths' ratio, without the lengths).
double FamilyStrain(const SpringLayout& layout, const double* HWY_RESTRICT length) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d);
  V ratio = hn::Set(d, 1.0);
  for (const SpringFamily& fam : layout.families) {
    const double* HWY_RESTRICT rest = fam.rest.data();
    const double* HWY_RESTRICT l_at = length + fam.slot_first;
    for (std::size_t k = 0; k < static_cast<std::size_t>(fam.count); k += N) {
      const V l0 = hn::LoadU(d, rest + k), l = hn::LoadU(d, l_at + k);
      ratio = window::GrowRatio(d, ratio, l, l0, hn::Gt(l0, zero));
    }
  }
  return window::WorstRatio(d, ratio);
}

// One family's terms over positions k .. k + n - 1 for FamilyPotentialTerms, in RunSingle's
// form (every pointer at position k, restrict); `sum_at`: position k's partial sum (k mod kSums).
HWY_NOINLINE void RunPotential(const SpringFamily& fam, double h, double damper_h, const double* HWY_RESTRICT rest,
                               const double* HWY_RESTRICT start_length, const double* HWY_RESTRICT ya,
                               const double* HWY_RESTRICT yb, double* HWY_RESTRICT plus,
                               double* HWY_RESTRICT minus, double* HWY_RESTRICT end_length,
                               double* HWY_RESTRICT phi, double* HWY_RESTRICT magnitude,
                               std::size_t sum_at, std::size_t stride, std::size_t n) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d);
  const V hv = hn::Set(d, h);
  // the family's constants, as spring_force.h rounds them
  const V ks = hn::Set(d, fam.ks), kdh = hn::Set(d, fam.kd / damper_h);
  const V half_ks = hn::Set(d, 0.5 * fam.ks), half_kdh = hn::Set(d, 0.5 * (fam.kd / damper_h));
  const std::size_t s1 = stride, s2 = 2 * stride;
  for (std::size_t k = 0; k < n; k += N) {
    const V l0 = hn::LoadU(d, rest + k);
    const V ln = hn::LoadU(d, start_length + k);
    const V dx = hn::Sub(hn::LoadU(d, ya + k), hn::LoadU(d, yb + k));
    const V dy = hn::Sub(hn::LoadU(d, ya + s1 + k), hn::LoadU(d, yb + s1 + k));
    const V dz = hn::Sub(hn::LoadU(d, ya + s2 + k), hn::LoadU(d, yb + s2 + k));
    const V l = window::Length(dx, dy, dz);
    const V stretch = hn::Sub(l, l0), rate = hn::Sub(l, ln);
    // E = 0.5 ks (l - l0)^2 + 0.5 (kd / h_d) (l - ln)^2, T = ks (l - l0) + (kd / h_d) (l - ln),
    // h_d the damper's step (h for backward Euler), ln the reference length
    const V e = hn::Add(hn::Mul(hn::Mul(half_ks, stretch), stretch), hn::Mul(hn::Mul(half_kdh, rate), rate));
    const V T = hn::Add(hn::Mul(ks, stretch), hn::Mul(kdh, rate));
    const M spring = hn::Gt(l0, zero);
    const M acts = hn::AndNot(hn::Le(l, zero), spring);  // a direction (or NaN)
    // (FamilyLengths' store: the same lengths by slot, for the next step's start)
    if (end_length) hn::StoreU(hn::IfThenElseZero(spring, l), d, end_length + k);
    const V e_in = hn::IfThenElseZero(spring, e);
    const V m_in = hn::Add(e_in, hn::IfThenElseZero(acts, hn::Mul(hn::Abs(T), l)));
    const std::size_t j = (sum_at + k) % kSums;
    hn::StoreU(hn::Add(hn::LoadU(d, phi + j), e_in), d, phi + j);
    hn::StoreU(hn::Add(hn::LoadU(d, magnitude + j), m_in), d, magnitude + j);
    const V c = hn::Div(hn::Mul(hv, T), l);  // push = (h T / l) d
    const V px = hn::IfThenElseZero(acts, hn::Mul(c, dx));
    const V py = hn::IfThenElseZero(acts, hn::Mul(c, dy));
    const V pz = hn::IfThenElseZero(acts, hn::Mul(c, dz));
    AddComponents(plus, k, stride, px, py, pz);
    AddComponents(minus, k, stride, hn::Neg(px), hn::Neg(py), hn::Neg(pz));  // x + -p: x - p's bits
  }
}

// Phi's spring terms and gradient: step_potential's loop body, lane by lane. sums: 2 kSums
// partial sums (phi, magnitude), zeroed by the caller.
void FamilyPotentialTerms(const SpringLayout& layout, const double* HWY_RESTRICT y,
                          const double* HWY_RESTRICT start_length, double h, double damper_h,
                          double* HWY_RESTRICT gradient, double* HWY_RESTRICT sums,
                          double* HWY_RESTRICT end_length, double* HWY_RESTRICT scratch,
                          std::size_t stride) {
  const Window w(scratch, stride);
  WalkRanges(layout, y, gradient, scratch, stride, w,
       [&](const SpringFamily& fam, const Range& r) {
         RunPotential(fam, h, damper_h, fam.rest.data() + r.k0, start_length + r.s, w.in[0] + r.a, w.in[0] + r.b,
                      w.plus[0] + r.a, w.minus[0] + r.b, end_length ? end_length + r.s : nullptr, sums,
                      sums + kSums, r.k0, stride, r.n);
       });
}

// Phi's body terms (step_potential.cpp's add_body_terms, lane by lane) and the end-of-step
// positions, N bodies at a time, their xyz read and written interleaved: y = x + h (v + dv);
// gradient = m dv - h m g (bodies with gravity) + drag_h c v (particles, air drag), zero on
// immovable bodies, written rather than added to (the spring passes add to it after); body i's
// energy into partial sum i mod kSums. A last partial vector runs on a padded copy.
void BodyTerms(const BodyArgs& args, double* HWY_RESTRICT y, double* HWY_RESTRICT gradient,
               double* HWY_RESTRICT sums) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d);
  const V one = hn::Set(d, 1.0);
  const V half = hn::Set(d, 0.5);
  const V h = hn::Set(d, args.h);
  const V gx = hn::Set(d, args.gravity[0]), gy = hn::Set(d, args.gravity[1]), gz = hn::Set(d, args.gravity[2]);
  const V h_drag = hn::Set(d, args.drag_h * args.drag);
  const V half_h_drag = hn::Set(d, 0.5 * args.drag_h * args.drag);
  const std::size_t B = args.bodies, P = args.particles;
  double* HWY_RESTRICT phi = sums;
  double* HWY_RESTRICT magnitude = sums + kSums;
  HWY_ALIGN double tail[3 * 3 * kSpringLanePad + 2 * kSpringLanePad];
  HWY_ALIGN double tail_out[2 * 3 * kSpringLanePad];
  HWY_ALIGN double factor[2 * kSpringLanePad];  // per lane: gravity on (1 or 0), drag on
  bool factors_all_on = false;                   // factor holds ones only
  for (std::size_t i = 0; i < B; i += N) {
    const std::size_t lanes = std::min(N, B - i);
    const double *x = args.x + 3 * i, *v = args.v + 3 * i, *dv = args.dv + 3 * i, *w_at = args.inv_mass + i;
    double *y_at = y + 3 * i, *g_at = gradient + 3 * i;
    if (lanes < N) {  // the last bodies, padded with immovable ones (no terms)
      std::fill(tail, tail + sizeof(tail) / sizeof(double), 0.0);
      std::copy(x, x + 3 * lanes, tail);
      std::copy(v, v + 3 * lanes, tail + 3 * N);
      std::copy(dv, dv + 3 * lanes, tail + 6 * N);
      std::copy(w_at, w_at + lanes, tail + 9 * N);
      x = tail, v = tail + 3 * N, dv = tail + 6 * N, w_at = tail + 9 * N;
      y_at = tail_out, g_at = tail_out + 3 * N;
    }
    // Which lanes have gravity and drag: all of them for a vector of cloth particles (the
    // common case, read as one comparison of N flag bytes), else lane by lane.
    static constexpr std::uint8_t kAllOn[kSpringLanePad] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    const bool all_on = lanes == N && i + N <= P && std::memcmp(args.gravity_on + i, kAllOn, N) == 0;
    if (!all_on) {
      for (std::size_t j = 0; j < N; ++j) {
        factor[j] = j < lanes && args.gravity_on[i + j] ? 1.0 : 0.0;
        factor[N + j] = i + j < P ? 1.0 : 0.0;
      }
    } else if (!factors_all_on) {
      for (std::size_t j = 0; j < N; ++j) factor[j] = factor[N + j] = 1.0;
    }
    factors_all_on = all_on;
    V X, Y, Z, VX, VY, VZ, DX, DY, DZ;
    hn::LoadInterleaved3(d, x, X, Y, Z);
    hn::LoadInterleaved3(d, v, VX, VY, VZ);
    hn::LoadInterleaved3(d, dv, DX, DY, DZ);
    const V vx = hn::Add(VX, DX), vy = hn::Add(VY, DY), vz = hn::Add(VZ, DZ);  // v_n + dv
    hn::StoreInterleaved3(hn::Add(X, hn::Mul(h, vx)), hn::Add(Y, hn::Mul(h, vy)), hn::Add(Z, hn::Mul(h, vz)), d, y_at);
    const V w = hn::LoadU(d, w_at);
    const M moves = hn::Ne(w, zero);
    const M gravity = hn::And(moves, hn::Ne(hn::Load(d, factor), zero));
    const M drag = hn::And(moves, hn::Ne(hn::Load(d, factor + N), zero));
    const V m = hn::Div(one, w);
    const V hm = hn::Mul(h, m);
    // inertia 1/2 m |dv|^2, gravity's work h m g . v, drag's dissipation 1/2 h c |v|^2
    const V inertia = hn::IfThenElseZero(
        moves, hn::Mul(hn::Mul(half, m), hn::Add(hn::Add(hn::Mul(DX, DX), hn::Mul(DY, DY)), hn::Mul(DZ, DZ))));
    const V work = hn::IfThenElseZero(
        gravity, hn::Mul(hm, hn::Add(hn::Add(hn::Mul(gx, vx), hn::Mul(gy, vy)), hn::Mul(gz, vz))));
    const V dissipation = hn::IfThenElseZero(
        drag, hn::Mul(half_h_drag, hn::Add(hn::Add(hn::Mul(vx, vx), hn::Mul(vy, vy)), hn::Mul(vz, vz))));
    const std::size_t k = i % kSums;
    hn::StoreU(hn::Add(hn::LoadU(d, phi + k), hn::Add(hn::Sub(inertia, work), dissipation)), d, phi + k);
    hn::StoreU(hn::Add(hn::LoadU(d, magnitude + k), hn::Add(hn::Add(inertia, hn::Abs(work)), dissipation)), d,
               magnitude + k);
    const auto component = [&](V dvc, V vc, V gc) {
      const V g = hn::Sub(hn::Mul(m, dvc), hn::IfThenElseZero(gravity, hn::Mul(hm, gc)));
      return hn::IfThenElseZero(moves, hn::Add(g, hn::IfThenElseZero(drag, hn::Mul(h_drag, vc))));
    };
    hn::StoreInterleaved3(component(DX, vx, gx), component(DY, vy, gy), component(DZ, vz, gz), d, g_at);
    if (lanes < N) {
      std::copy(tail_out, tail_out + 3 * lanes, y + 3 * i);
      std::copy(tail_out + 3 * N, tail_out + 3 * N + 3 * lanes, gradient + 3 * i);
    }
  }
}

// One family's springs over positions k .. k + n - 1 for FamilyMultiply: every pointer already
// at position k (blocks by slot, rest lengths by position, window arrays at the springs' a or
// b), and restrict, so that the vector stores (which may alias anything) do not reload them.
HWY_NOINLINE void RunDouble(const double* HWY_RESTRICT ux, const double* HWY_RESTRICT uy,
                            const double* HWY_RESTRICT uz, const double* HWY_RESTRICT alpha,
                            const double* HWY_RESTRICT beta, const double* HWY_RESTRICT rest,
                            const double* HWY_RESTRICT pa, const double* HWY_RESTRICT pb,
                            double* HWY_RESTRICT plus, double* HWY_RESTRICT minus,
                            std::size_t stride, std::size_t n) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d);
  const std::size_t s1 = stride, s2 = 2 * stride;
  for (std::size_t k = 0; k < n; k += N) {
    const V vx = hn::LoadU(d, ux + k), vy = hn::LoadU(d, uy + k), vz = hn::LoadU(d, uz + k);
    const V al = hn::LoadU(d, alpha + k), c = hn::LoadU(d, beta + k);
    const V pa0 = hn::LoadU(d, pa + k), pa1 = hn::LoadU(d, pa + s1 + k), pa2 = hn::LoadU(d, pa + s2 + k);
    const V pb0 = hn::LoadU(d, pb + k), pb1 = hn::LoadU(d, pb + s1 + k), pb2 = hn::LoadU(d, pb + s2 + k);
    const V sa = hn::Mul(al, hn::Add(hn::Add(hn::Mul(vx, pa0), hn::Mul(vy, pa1)), hn::Mul(vz, pa2)));
    const V sb = hn::Mul(al, hn::Add(hn::Add(hn::Mul(vx, pb0), hn::Mul(vy, pb1)), hn::Mul(vz, pb2)));
    // A position without a spring holds zeros, but 0 p is NaN where p is: masked.
    const M m = hn::Gt(hn::LoadU(d, rest + k), zero);
    const V ya0 = hn::IfThenElseZero(m, hn::Add(hn::Mul(sb, vx), hn::Mul(c, pb0)));
    const V ya1 = hn::IfThenElseZero(m, hn::Add(hn::Mul(sb, vy), hn::Mul(c, pb1)));
    const V ya2 = hn::IfThenElseZero(m, hn::Add(hn::Mul(sb, vz), hn::Mul(c, pb2)));
    const V yb0 = hn::IfThenElseZero(m, hn::Add(hn::Mul(sa, vx), hn::Mul(c, pa0)));
    const V yb1 = hn::IfThenElseZero(m, hn::Add(hn::Mul(sa, vy), hn::Mul(c, pa1)));
    const V yb2 = hn::IfThenElseZero(m, hn::Add(hn::Mul(sa, vz), hn::Mul(c, pa2)));
    AddComponents(plus, k, stride, ya0, ya1, ya2);
    AddComponents(minus, k, stride, yb0, yb1, yb2);
  }
}

// out = D p + the families' blocks applied to p: sparse_system.cpp's multiply, lane by lane.
std::size_t FamilyMultiply(const SpringLayout& layout, const FamilyBlocks& blocks,
                    const double* HWY_RESTRICT p, double* HWY_RESTRICT out,
                    double* HWY_RESTRICT scratch, std::size_t stride) {
  const Window w(scratch, stride);
  return WalkRanges(layout, p, out, scratch, stride, w,
       [&](const SpringFamily& fam, const Range& r) {
         RunDouble(blocks.ux + r.s, blocks.uy + r.s, blocks.uz + r.s, blocks.alpha + r.s, blocks.beta + r.s,
                   fam.rest.data() + r.k0, w.in[0] + r.a, w.in[0] + r.b, w.plus[0] + r.a, w.minus[0] + r.b, stride,
                   r.n);
       },
       blocks.diag, blocks.bodies);
}

// One family's springs over positions k .. k + n - 1 for FamilyMultiplySingle: every pointer
// already at position k (copy numbers by slot; window arrays at the springs' a, or b), and
// restrict, so that the vector stores (which may alias anything) do not reload them.
HWY_NOINLINE void RunSingle(const float* HWY_RESTRICT ux, const float* HWY_RESTRICT uy,
                            const float* HWY_RESTRICT uz, const float* HWY_RESTRICT alpha,
                            const float* HWY_RESTRICT beta, const std::uint8_t* HWY_RESTRICT spring,
                            const double* HWY_RESTRICT pa, const double* HWY_RESTRICT pb,
                            double* HWY_RESTRICT plus, double* HWY_RESTRICT minus,
                            std::size_t stride, std::size_t n) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const hn::Rebind<std::int32_t, D> d32;
  const hn::Rebind<std::uint8_t, D> d8;
  const V zero = hn::Zero(d);
  const std::size_t s1 = stride, s2 = 2 * stride;
  for (std::size_t k = 0; k < n; k += N) {
    const V vx = LoadAsDouble(d, ux + k), vy = LoadAsDouble(d, uy + k), vz = LoadAsDouble(d, uz + k);
    const V al = LoadAsDouble(d, alpha + k), c = LoadAsDouble(d, beta + k);
    const V d0 = hn::Sub(hn::LoadU(d, pb + k), hn::LoadU(d, pa + k));
    const V d1 = hn::Sub(hn::LoadU(d, pb + s1 + k), hn::LoadU(d, pa + s1 + k));
    const V d2 = hn::Sub(hn::LoadU(d, pb + s2 + k), hn::LoadU(d, pa + s2 + k));
    const V along = hn::Mul(al, hn::Add(hn::Add(hn::Mul(vx, d0), hn::Mul(vy, d1)), hn::Mul(vz, d2)));
    // G (p_b - p_a), masked as in RunDouble
    const M m = hn::Ne(hn::PromoteTo(d, hn::PromoteTo(d32, hn::LoadU(d8, spring + k))), zero);
    const V g0 = hn::IfThenElseZero(m, hn::Add(hn::Mul(along, vx), hn::Mul(c, d0)));
    const V g1 = hn::IfThenElseZero(m, hn::Add(hn::Mul(along, vy), hn::Mul(c, d1)));
    const V g2 = hn::IfThenElseZero(m, hn::Add(hn::Mul(along, vz), hn::Mul(c, d2)));
    AddComponents(plus, k, stride, g0, g1, g2);
    AddComponents(minus, k, stride, hn::Neg(g0), hn::Neg(g1), hn::Neg(g2));  // x + -g: x - g's bits
  }
}

// out = R p + each family spring's block G on p_b - p_a at a and on p_a - p_b at b: the same
// product as FamilyMultiply's (R = D + the blocks at i), on the float copy's numbers widened.
std::size_t FamilyMultiplySingle(const SpringLayout& layout, const FamilySingleBlocks& blocks,
                                 const double* HWY_RESTRICT p, double* HWY_RESTRICT out,
                                 double* HWY_RESTRICT scratch, std::size_t stride) {
  const Window w(scratch, stride);
  return WalkRanges(layout, p, out, scratch, stride, w,
       [&](const SpringFamily&, const Range& r) {
         RunSingle(blocks.ux + r.s, blocks.uy + r.s, blocks.uz + r.s, blocks.alpha + r.s, blocks.beta + r.s,
                   blocks.spring + r.s, w.in[0] + r.a, w.in[0] + r.b, w.plus[0] + r.a, w.minus[0] + r.b, stride,
                   r.n);
       },
       blocks.rest, blocks.bodies);
}

const char* PotentialTargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(FamilyLengths);
HWY_EXPORT(FamilyStrain);
HWY_EXPORT(FamilyPotentialTerms);
HWY_EXPORT(FamilyMultiply);
HWY_EXPORT(FamilyMultiplySingle);
HWY_EXPORT(BodyTerms);
HWY_EXPORT(PotentialTargetName);

namespace {

// Scratch per thread (compare runs lanes on threads), grown, never shrunk: a window of about
// kWindowBlock + 2 nx particles.
struct Scratch {
  double* data;
  std::size_t stride;
};
Scratch scratch_for(const SpringLayout& layout) {
  thread_local hwy::AlignedFreeUniquePtr<double[]> scratch;
  thread_local std::size_t capacity = 0;
  const std::size_t stride = window_stride(layout);
  if (kArrays * stride > capacity) {
    capacity = kArrays * stride;
    scratch = hwy::AllocateAligned<double>(capacity);
  }
  return {scratch.get(), stride};
}

}  // namespace

double family_step_lengths(const SpringLayout& layout, const Eigen::Matrix3Xd& x, double* length) {
  const Scratch s = scratch_for(layout);
  return HWY_DYNAMIC_DISPATCH(FamilyLengths)(layout, x.data(), length, s.data, s.stride);
}

double family_strain(const SpringLayout& layout, const double* length) {
  return HWY_DYNAMIC_DISPATCH(FamilyStrain)(layout, length);
}

FamilyPotential family_step_potential(const SpringLayout& layout, const Eigen::Matrix3Xd& y,
                                      const double* start_length, const StepForm& form,
                                      Eigen::Matrix3Xd& gradient, double* end_length) {
  const Scratch s = scratch_for(layout);
  alignas(64) double sums[2 * kSums] = {};
  HWY_DYNAMIC_DISPATCH(FamilyPotentialTerms)(layout, y.data(), start_length, form.h, form.damper_h, gradient.data(),
                                             sums, end_length, s.data, s.stride);
  FamilyPotential out;
  for (std::size_t j = 0; j < kSums; ++j) {  // in a fixed order (above)
    out.phi += sums[j];
    out.magnitude += sums[kSums + j];
  }
  return out;
}

FamilyPotential body_terms(const BodyArgs& args, Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient) {
  y.resize(3, static_cast<Eigen::Index>(args.bodies));
  gradient.resize(3, static_cast<Eigen::Index>(args.bodies));
  alignas(64) double sums[2 * kSums] = {};
  HWY_DYNAMIC_DISPATCH(BodyTerms)(args, y.data(), gradient.data(), sums);
  FamilyPotential out;
  for (std::size_t j = 0; j < kSums; ++j) {  // in a fixed order
    out.phi += sums[j];
    out.magnitude += sums[kSums + j];
  }
  return out;
}

std::size_t family_multiply(const SpringLayout& layout, const FamilyBlocks& blocks,
                            const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& out) {
  const Scratch s = scratch_for(layout);
  return HWY_DYNAMIC_DISPATCH(FamilyMultiply)(layout, blocks, p.data(), out.data(), s.data, s.stride);
}

std::size_t family_multiply_single(const SpringLayout& layout, const FamilySingleBlocks& blocks,
                                   const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& out) {
  const Scratch s = scratch_for(layout);
  return HWY_DYNAMIC_DISPATCH(FamilyMultiplySingle)(layout, blocks, p.data(), out.data(), s.data, s.stride);
}


const char* potential_kernel_target() { return HWY_DYNAMIC_DISPATCH(PotentialTargetName)(); }

}  // namespace clothsim
#endif  // HWY_ONCE
