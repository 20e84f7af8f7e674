// Highway's foreach_target.h compiles this file once per x86 target (SSE2 .. AVX-512), each
// copy inside its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick the copy at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "spring_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

#include "spring_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;

// (3 x P) interleaved xyz -> three arrays of P.
void Deinterleave(const double* HWY_RESTRICT in, std::size_t P, double* HWY_RESTRICT xs,
                  double* HWY_RESTRICT ys, double* HWY_RESTRICT zs) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t p = 0;
  for (; p + N <= P; p += N) {
    hn::Vec<D> X, Y, Z;
    hn::LoadInterleaved3(d, in + 3 * p, X, Y, Z);
    hn::StoreU(X, d, xs + p);
    hn::StoreU(Y, d, ys + p);
    hn::StoreU(Z, d, zs + p);
  }
  for (; p < P; ++p) {
    xs[p] = in[3 * p];
    ys[p] = in[3 * p + 1];
    zs[p] = in[3 * p + 2];
  }
}

// out (3 x P, interleaved) += a + b, per component.
void AddInterleaved(const double* HWY_RESTRICT ax, const double* HWY_RESTRICT ay,
                    const double* HWY_RESTRICT az, const double* HWY_RESTRICT bx,
                    const double* HWY_RESTRICT by, const double* HWY_RESTRICT bz, std::size_t P,
                    double* HWY_RESTRICT out) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  std::size_t p = 0;
  for (; p + N <= P; p += N) {
    hn::Vec<D> X, Y, Z;
    hn::LoadInterleaved3(d, out + 3 * p, X, Y, Z);
    X = hn::Add(X, hn::Add(hn::LoadU(d, ax + p), hn::LoadU(d, bx + p)));
    Y = hn::Add(Y, hn::Add(hn::LoadU(d, ay + p), hn::LoadU(d, by + p)));
    Z = hn::Add(Z, hn::Add(hn::LoadU(d, az + p), hn::LoadU(d, bz + p)));
    hn::StoreInterleaved3(X, Y, Z, d, out + 3 * p);
  }
  for (; p < P; ++p) {
    out[3 * p] += ax[p] + bx[p];
    out[3 * p + 1] += ay[p] + by[p];
    out[3 * p + 2] += az[p] + bz[p];
  }
}

// The families' forces into f; `scratch` holds 12 arrays of `stride` doubles (x, v, and the
// two force accumulators, each as three components). Returns the largest l / l0.
double FamilySpringForces(const SpringLayout& layout, const double* HWY_RESTRICT x,
                          const double* HWY_RESTRICT v, double* HWY_RESTRICT f,
                          double* HWY_RESTRICT scratch, std::size_t stride) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const std::size_t P = static_cast<std::size_t>(layout.num_particles);
  double* HWY_RESTRICT xs = scratch;  // (P + pad) each; the pad is zero
  double* HWY_RESTRICT ys = xs + stride;
  double* HWY_RESTRICT zs = ys + stride;
  double* HWY_RESTRICT vxs = zs + stride;
  double* HWY_RESTRICT vys = vxs + stride;
  double* HWY_RESTRICT vzs = vys + stride;
  double* HWY_RESTRICT fpx = vzs + stride;  // + the force on each spring's a
  double* HWY_RESTRICT fpy = fpx + stride;
  double* HWY_RESTRICT fpz = fpy + stride;
  double* HWY_RESTRICT fmx = fpz + stride;  // - the force on each spring's a, at its b
  double* HWY_RESTRICT fmy = fmx + stride;
  double* HWY_RESTRICT fmz = fmy + stride;

  Deinterleave(x, P, xs, ys, zs);
  Deinterleave(v, P, vxs, vys, vzs);
  for (double* a : {xs, ys, zs, vxs, vys, vzs}) std::fill(a + P, a + stride, 0.0);
  std::fill(fpx, fpx + 6 * stride, 0.0);

  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0);
  auto ratio = one;  // per lane: the largest l / l0 so far
  for (const SpringFamily& fam : layout.families) {
    const double* HWY_RESTRICT rest = fam.rest.data();
    const std::size_t first = static_cast<std::size_t>(fam.first);
    const std::size_t off = static_cast<std::size_t>(fam.offset);
    const std::size_t count = static_cast<std::size_t>(fam.count);
    const auto minus_ks = hn::Set(d, -fam.ks);
    const auto kd = hn::Set(d, fam.kd);
    // The last vector may run past `count` (rest is padded with zeros: no spring) and past P
    // (the scratch is padded): those lanes are masked out below.
    for (std::size_t k = 0; k < count; k += N) {
      const std::size_t a = first + k, b = a + off;
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
      const auto grows = hn::And(spring, hn::Or(hn::And(hn::Gt(l, zero), hn::Ge(l, hn::Mul(ratio, l0))),
                                                hn::IsNaN(l)));
      if (!hn::AllFalse(d, grows)) {
        const auto q = hn::Div(l, l0);
        ratio = hn::IfThenElse(hn::AndNot(hn::Le(q, ratio), grows), q, ratio);
      }
    }
  }
  AddInterleaved(fpx, fpy, fpz, fmx, fmy, fmz, P, f);

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
  // Scratch per thread (compare runs lanes on threads), grown, never shrunk.
  thread_local hwy::AlignedFreeUniquePtr<double[]> scratch;
  thread_local std::size_t capacity = 0;
  // Each array 64-byte aligned: a multiple of 8 doubles apart.
  const std::size_t stride = (static_cast<std::size_t>(layout.num_particles) + kSpringLanePad + 7) / 8 * 8;
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
