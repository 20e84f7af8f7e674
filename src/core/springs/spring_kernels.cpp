// Highway's foreach_target.h compiles this file once per x86 target (Highway 1.0's: SCALAR for
// plain x86-64, SSSE3, SSE4, AVX2, AVX3 = AVX-512), each copy inside its own namespace;
// HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick the copy at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/springs/spring_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "spring_kernels.h"
#include "spring_window-inl.h"  // the walk over the families: its window and helpers
#include "core/base/body_terms.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
static_assert(HWY_MAX_BYTES / sizeof(double) <= kSpringLanePad, "the layout's padding is a vector");

// Particles [particle, particle + n) finished by the walk: f_i = 0 + (plus + minus), as
// AddInterleaved adds the sums onto a zeroed f, then body_terms()'s operations in its order, in
// whole vectors (the sums and v at window index `at` on, each component `stride` apart).
void FinishParticles(const BodyTermInputs& in, const double* HWY_RESTRICT plus, const double* HWY_RESTRICT minus,
                     const double* HWY_RESTRICT vel, std::size_t stride, std::size_t n, std::size_t particle,
                     double* HWY_RESTRICT f) {
  const D d;
  const hn::Rebind<std::int32_t, D> d32;
  const hn::Rebind<std::uint8_t, D> d8;
  const std::size_t N = hn::Lanes(d);
  const auto zero = hn::Zero(d);
  const auto gx = hn::Set(d, in.g[0]), gy = hn::Set(d, in.g[1]), gz = hn::Set(d, in.g[2]);
  const auto drag = hn::Set(d, in.drag);
  const auto sum = [&](std::size_t c, std::size_t j) {
    return hn::Add(zero, hn::Add(hn::LoadU(d, plus + c * stride + j), hn::LoadU(d, minus + c * stride + j)));
  };
  std::size_t p = 0;
  for (; p + N <= n; p += N) {
    const std::size_t i = particle + p;
    auto fx = sum(0, p), fy = sum(1, p), fz = sum(2, p);
    const auto w = hn::LoadU(d, in.inv_mass + i);
    const auto m = hn::LoadU(d, in.mass + i);
    const auto gravity = hn::Ne(hn::PromoteTo(d, hn::PromoteTo(d32, hn::LoadU(d8, in.gravity_on + i))), zero);
    fx = hn::IfThenElse(gravity, hn::Add(fx, hn::Mul(m, gx)), fx);
    fy = hn::IfThenElse(gravity, hn::Add(fy, hn::Mul(m, gy)), fy);
    fz = hn::IfThenElse(gravity, hn::Add(fz, hn::Mul(m, gz)), fz);
    if (in.drag != 0.0) {  // every particle the walk finishes is cloth
      fx = hn::Sub(fx, hn::Mul(drag, hn::LoadU(d, vel + p)));
      fy = hn::Sub(fy, hn::Mul(drag, hn::LoadU(d, vel + stride + p)));
      fz = hn::Sub(fz, hn::Mul(drag, hn::LoadU(d, vel + 2 * stride + p)));
    }
    if (in.times_inverse_mass) fx = hn::Mul(fx, w), fy = hn::Mul(fy, w), fz = hn::Mul(fz, w);
    const auto movable = hn::Ne(w, zero);  // immovable: exactly +0
    hn::StoreInterleaved3(hn::IfThenElseZero(movable, fx), hn::IfThenElseZero(movable, fy),
                          hn::IfThenElseZero(movable, fz), d, f + 3 * i);
  }
  for (; p < n; ++p) {
    double* fi = f + 3 * (particle + p);
    for (std::size_t c = 0; c < 3; ++c) fi[c] = 0.0 + (plus[c * stride + p] + minus[c * stride + p]);
    body_terms(in, particle + p, fi);
  }
}

// The families' forces into f; `scratch` holds 12 window arrays of `stride` >= window_of(layout)
// doubles (x, v, and the two force sums, each as three components; spring_window-inl.h's walk).
// Returns the largest l / l0. A particle's forces are summed in (block, family) order: fixed,
// whatever the lane count.
// With `terms`, each particle's sum is instead written into f with its body terms applied
// (body_terms.h), and *finished says how many particles were (0 .. F: the rest no spring
// reaches, and f's columns from F on are not touched).
double FamilySpringForces(const SpringLayout& layout, const double* HWY_RESTRICT x,
                          const double* HWY_RESTRICT v, double* HWY_RESTRICT f,
                          double* HWY_RESTRICT scratch, std::size_t stride,
                          const BodyTermInputs* terms, std::size_t* finished) {
  const D d;
  const std::size_t N = hn::Lanes(d);
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

  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0);
  auto ratio = one;  // per lane: the largest l / l0 so far
  const auto copy_in = [&](std::size_t particle, std::size_t n, std::size_t at) {
    window::Deinterleave(x + 3 * particle, n, xs + at, ys + at, zs + at);
    window::Deinterleave(v + 3 * particle, n, vxs + at, vys + at, vzs + at);
  };
  const auto body = [&](const SpringFamily& fam, std::size_t k0, std::size_t k1, std::size_t first) {
    const double* HWY_RESTRICT rest = fam.rest.data();
    const std::size_t off = static_cast<std::size_t>(fam.offset);
    const auto minus_ks = hn::Set(d, -fam.ks);
    const auto kd = hn::Set(d, fam.kd);
    // The family's last vector may run past `count` (rest is padded with zeros: no spring)
    // and past P (zeros in the window): those lanes are masked out below.
    for (std::size_t k = k0; k < k1; k += N) {
      const std::size_t a = first + k, b = a + off;  // window indices
      HWY_DASSERT(b + N <= stride);  // debug builds: the window holds what the block touches
      const auto l0 = hn::LoadU(d, rest + k);
      const auto dx = hn::Sub(hn::LoadU(d, xs + a), hn::LoadU(d, xs + b));
      const auto dy = hn::Sub(hn::LoadU(d, ys + a), hn::LoadU(d, ys + b));
      const auto dz = hn::Sub(hn::LoadU(d, zs + a), hn::LoadU(d, zs + b));
      const auto l = window::Length(dx, dy, dz);
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
      ratio = window::GrowRatio(d, ratio, l, l0, spring);  // the strain, as the scalar pass
    }
  };
  const auto flush = [&](std::size_t particle, std::size_t n, std::size_t at) {
    if (terms) return FinishParticles(*terms, fpx + at, fmx + at, vxs + at, stride, n, particle, f);
    const double* const plus[] = {fpx + at, fpy + at, fpz + at};
    const double* const minus[] = {fmx + at, fmy + at, fmz + at};
    window::AddInterleaved(plus, minus, n, f + 3 * particle);
  };
  const std::size_t flushed = window::WalkFamilies(layout, scratch, stride, 6, 6, copy_in, body, flush);
  if (finished) *finished = flushed;

  return window::WorstRatio(d, ratio);
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(FamilySpringForces);
HWY_EXPORT(TargetName);

namespace {

// Scratch per thread (compare runs lanes on threads), grown, never shrunk: a window of about
// kWindowBlock + 2 nx particles, not the whole grid. 12 arrays of window_stride(layout).
double* window_scratch(const SpringLayout& layout) {
  thread_local hwy::AlignedFreeUniquePtr<double[]> scratch;
  thread_local std::size_t capacity = 0;
  const std::size_t stride = window_stride(layout);
  if (12 * stride > capacity) {
    capacity = 12 * stride;
    scratch = hwy::AllocateAligned<double>(capacity);
  }
  return scratch.get();
}

}  // namespace

double accumulate_family_spring_forces(const SpringLayout& layout, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  return HWY_DYNAMIC_DISPATCH(FamilySpringForces)(layout, x.data(), v.data(), f.data(), window_scratch(layout),
                                                  window_stride(layout), nullptr, nullptr);
}

double family_forces_with_body_terms(const SpringLayout& layout, const Eigen::Matrix3Xd& x,
                                     const Eigen::Matrix3Xd& v, const BodyTermInputs& terms,
                                     Eigen::Matrix3Xd& f, std::size_t& finished) {
  return HWY_DYNAMIC_DISPATCH(FamilySpringForces)(layout, x.data(), v.data(), f.data(), window_scratch(layout),
                                                  window_stride(layout), &terms, &finished);
}

const char* spring_kernel_target() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace clothsim
#endif  // HWY_ONCE
