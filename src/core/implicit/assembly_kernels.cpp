// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick one at
// run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/implicit/assembly_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "assembly_kernels.h"
#include "core/springs/spring_force.h"
#include "core/springs/spring_window-inl.h"  // the walk over the families: its window and helpers

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;
static_assert(HWY_MAX_BYTES / sizeof(double) <= kSpringLanePad, "the layout's padding is a vector");

// The sum of the blocks alpha u u^T + beta I of the springs whose a, then whose b, is one of
// particles p .. p+N-1, family after family in a fixed order, as the six entries of their
// diagonal blocks (xx, yy, zz, xy, xz, yz): the slots s .. s+N-1 of the springs at a = p are
// slot_first - first + p, one offset further back for those at b = p (vectors that meet the
// family only: the slot order's gaps keep the reads within its slots).
HWY_INLINE void SumBlocksAt(const SpringLayout& layout, std::size_t p, const double* HWY_RESTRICT ux,
                            const double* HWY_RESTRICT uy, const double* HWY_RESTRICT uz,
                            const double* HWY_RESTRICT alpha, const double* HWY_RESTRICT beta, V (&sum)[6]) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  // (six named sums rather than the array: kept in registers, not zeroed and summed on the stack)
  V xx = hn::Zero(d), yy = xx, zz = xx, xy = xx, xz = xx, yz = xx;
  const auto add = [&](std::size_t s) {  // the blocks at slots s .. s+N-1
    const V x = hn::LoadU(d, ux + s), y = hn::LoadU(d, uy + s), z = hn::LoadU(d, uz + s);
    const V al = hn::LoadU(d, alpha + s), be = hn::LoadU(d, beta + s);
    const V ax = hn::Mul(al, x), ay = hn::Mul(al, y), az = hn::Mul(al, z);
    xx = hn::Add(xx, hn::Add(hn::Mul(ax, x), be));
    yy = hn::Add(yy, hn::Add(hn::Mul(ay, y), be));
    zz = hn::Add(zz, hn::Add(hn::Mul(az, z), be));
    xy = hn::Add(xy, hn::Mul(ax, y));
    xz = hn::Add(xz, hn::Mul(ax, z));
    yz = hn::Add(yz, hn::Mul(ay, z));
  };
  for (const SpringFamily& fam : layout.families) {
    const std::size_t first = static_cast<std::size_t>(fam.first), count = static_cast<std::size_t>(fam.count);
    const std::size_t off = static_cast<std::size_t>(fam.offset);
    if (p + N > first && p < first + count) add(fam.slot_first + p - first);
    if (p + N > first + off && p < first + off + count) add(fam.slot_first + p - first - off);
  }
  sum[0] = xx, sum[1] = yy, sum[2] = zz, sum[3] = xy, sum[4] = xz, sum[5] = yz;
}

// The families' Newton blocks: sparse_system.cpp's assembly (assemble_step_hessian_scalar),
// lane by lane, in two passes. Long on purpose (a kernel): both passes read the same
// copied-in window of lanes and write through the same restrict-qualified outputs.
//  1. Over the springs (the walk, with y and the inverse masses in the window): each block's u
//     and (alpha, beta), exact and projected, stored by slot, for now also where an end is
//     immovable (the block still counts in the other end's diagonal).
//  2. Over the particles: each diagonal block, M + h c I minus the blocks of the springs whose
//     a or whose b it is, read from the slots by particle (slot_first - first + p for the
//     springs at a = p, one offset further back for those at b = p: contiguous loads, no
//     scatter, no sums kept in between), family after family in a fixed order.
// With out.rest_soa, pass 2 also writes R (the part of the matrix the float mat-vec applies
// per particle, SpringBlockMatrix::single): D plus the blocks at p is M + h c I, or I where p is
// immovable. The caller (family_assemble) then takes the springs to immovable bodies out of R,
// and zeroes their blocks (their rows and columns are removed).
std::size_t FamilyAssemble(const SpringLayout& layout, const double* HWY_RESTRICT y,
                           const double* HWY_RESTRICT inv_mass, const double* HWY_RESTRICT start_length,
                           const FamilyHessian& out, std::vector<std::int32_t>& filtered,
                           double* HWY_RESTRICT scratch, std::size_t stride) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d);
  const V one = hn::Set(d, 1.0);
  const double h = out.h;
  const V minus_h2 = hn::Set(d, -(h * h));  // the scalar code's -h2 * (...)
  const bool project = out.project;
  double* in[4];  // y, the inverse masses
  for (int c = 0; c < 4; ++c) in[c] = scratch + c * stride;
  filtered.clear();

  const auto copy_in = [&](std::size_t particle, std::size_t n, std::size_t at) {
    window::Deinterleave(y + 3 * particle, n, in[0] + at, in[1] + at, in[2] + at);
    std::copy(inv_mass + particle, inv_mass + particle + n, in[3] + at);
  };
  // (the outputs in locals: stores through a double* could otherwise alias `out`'s pointers)
  double* HWY_RESTRICT out_ux = out.ux;
  double* HWY_RESTRICT out_uy = out.uy;
  double* HWY_RESTRICT out_uz = out.uz;
  double* HWY_RESTRICT out_alpha = out.alpha;
  double* HWY_RESTRICT out_beta = out.beta;
  double* HWY_RESTRICT out_alpha_projected = out.alpha_projected;
  double* HWY_RESTRICT out_beta_projected = out.beta_projected;
  const auto blocks = [&](const SpringFamily& fam, std::size_t k0, std::size_t k1, std::size_t first) {
    const double* HWY_RESTRICT rest = fam.rest.data();
    const double* HWY_RESTRICT ys = in[0];
    const double* HWY_RESTRICT ys1 = in[1];
    const double* HWY_RESTRICT ys2 = in[2];
    const double* HWY_RESTRICT ws = in[3];
    const std::size_t off = static_cast<std::size_t>(fam.offset);
    const V ks = hn::Set(d, fam.ks), kdh = hn::Set(d, fam.kd / out.damper_h);
    const V axial = hn::Set(d, fam.ks + fam.kd / out.damper_h);  // spring_force.h's step_spring_block
    for (std::size_t k = k0; k < k1; k += N) {
      const std::size_t a = first + k, b = a + off, s = fam.slot_first + k;
      HWY_DASSERT(b + N <= stride);
      const V l0 = hn::LoadU(d, rest + k);
      const V ln = hn::LoadU(d, start_length + s);
      const V dx = hn::Sub(hn::LoadU(d, ys + a), hn::LoadU(d, ys + b));
      const V dy = hn::Sub(hn::LoadU(d, ys1 + a), hn::LoadU(d, ys1 + b));
      const V dz = hn::Sub(hn::LoadU(d, ys2 + a), hn::LoadU(d, ys2 + b));
      const V l = window::Length(dx, dy, dz);
      const M spring = hn::Gt(l0, zero);
      const M apart = hn::Not(hn::Le(l, zero));  // a direction (or NaN)
      // u = d / l and the transverse stiffness T / l through one division; a spring of
      // length 0 has no direction: u = 0, transverse = axial (an isotropic block).
      const V inv_l = hn::Div(one, l);
      const V ux = hn::IfThenElseZero(apart, hn::Mul(dx, inv_l));
      const V uy = hn::IfThenElseZero(apart, hn::Mul(dy, inv_l));
      const V uz = hn::IfThenElseZero(apart, hn::Mul(dz, inv_l));
      const V T = hn::Add(hn::Mul(ks, hn::Sub(l, l0)), hn::Mul(kdh, hn::Sub(l, ln)));
      const V t = hn::IfThenElse(apart, hn::Mul(T, inv_l), axial);
      const V t_projected = hn::IfThenElse(hn::Lt(t, zero), zero, t);  // NaN stays NaN
      const V alpha_projected = hn::Mul(minus_h2, hn::Sub(axial, t_projected));
      const V beta_projected = hn::Mul(minus_h2, t_projected);
      hn::StoreU(hn::IfThenElseZero(spring, ux), d, out_ux + s);
      hn::StoreU(hn::IfThenElseZero(spring, uy), d, out_uy + s);
      hn::StoreU(hn::IfThenElseZero(spring, uz), d, out_uz + s);
      hn::StoreU(hn::IfThenElseZero(spring, project ? alpha_projected : hn::Mul(minus_h2, hn::Sub(axial, t))),
                 d, out_alpha + s);
      hn::StoreU(hn::IfThenElseZero(spring, project ? beta_projected : hn::Mul(minus_h2, t)), d, out_beta + s);
      hn::StoreU(hn::IfThenElseZero(spring, alpha_projected), d, out_alpha_projected + s);
      hn::StoreU(hn::IfThenElseZero(spring, beta_projected), d, out_beta_projected + s);
      const M pinned = hn::And(spring, hn::Or(hn::Eq(hn::LoadU(d, ws + a), zero),
                                              hn::Eq(hn::LoadU(d, ws + b), zero)));
      if (!hn::AllFalse(d, pinned)) {  // rare: springs at pinned particles
        for (std::size_t j = 0; j < N; ++j)
          if ((ws[a + j] == 0.0 || ws[b + j] == 0.0) && rest[k + j] > 0.0)
            filtered.push_back(static_cast<std::int32_t>(s + j));
      }
    }
  };
  window::WalkFamilies(layout, scratch, stride, 4, 0, copy_in, blocks, [](std::size_t, std::size_t, std::size_t) {});

  // Pass 2, N particles at a time (a last partial vector reads its inverse masses from a copy).
  const std::size_t P = static_cast<std::size_t>(layout.num_particles);
  const V h_drag = hn::Set(d, out.drag_h * out.drag);
  HWY_ALIGN double entry[6][kSpringLanePad];
  HWY_ALIGN double tail[kSpringLanePad];
  HWY_ALIGN float rounded[kSpringLanePad];
  const hn::Rebind<float, D> df;
  const std::size_t sets = project ? 1 : 2;
  for (std::size_t p = 0; p < P; p += N) {
    const std::size_t lanes = std::min(N, P - p);
    const double* w_at = inv_mass + p;
    if (lanes < N) {
      std::fill(tail, tail + N, 1.0);
      std::copy(inv_mass + p, inv_mass + P, tail);
      w_at = tail;
    }
    const V w = hn::LoadU(d, w_at);
    const M moves = hn::Ne(w, zero);
    const V base = hn::Add(hn::Div(one, w), h_drag);
    if (out.rest_soa) {  // R = D + the blocks at p: M + h c I, or I where p is immovable
      const auto r = hn::DemoteTo(df, hn::IfThenElse(moves, base, one));
      const auto r0 = hn::Zero(df);
      for (int e = 0; e < 6; ++e) {
        float* at = out.rest_soa + e * out.bodies + p;
        if (lanes == N) {
          hn::StoreU(e < 3 ? r : r0, df, at);
        } else {
          hn::StoreU(e < 3 ? r : r0, df, rounded);
          std::copy(rounded, rounded + lanes, at);
        }
      }
    }
    for (std::size_t set = 0; set < sets; ++set) {  // the matrix's blocks, then the projected ones
      const double* HWY_RESTRICT alpha = set == 0 ? out_alpha : out_alpha_projected;
      const double* HWY_RESTRICT beta = set == 0 ? out_beta : out_beta_projected;
      V sum[6];  // xx, yy, zz, xy, xz, yz
      SumBlocksAt(layout, p, out_ux, out_uy, out_uz, alpha, beta, sum);
      for (int e = 0; e < 6; ++e) {
        const V value = e < 3 ? hn::Sub(base, sum[e]) : hn::Neg(sum[e]);
        const V stored = hn::IfThenElse(moves, value, e < 3 ? one : zero);
        hn::Store(stored, d, entry[e]);
        if (set == 0) {  // the matrix's blocks again, as structure of arrays (diag_soa)
          double* soa = out.diag_soa + e * out.bodies + p;
          if (lanes == N) hn::StoreU(stored, d, soa);
          else std::copy(entry[e], entry[e] + lanes, soa);
        }
      }
      double* HWY_RESTRICT diag = (set == 0 ? out.diag : out.diag_projected) + 9 * p;
      for (std::size_t j = 0; j < lanes; ++j, diag += 9) {
        diag[0] = entry[0][j];
        diag[4] = entry[1][j];
        diag[8] = entry[2][j];
        diag[1] = diag[3] = entry[3][j];
        diag[2] = diag[6] = entry[4][j];
        diag[5] = diag[7] = entry[5][j];
      }
    }
  }
  return P;
}

// R_i = D_i + the blocks stored at particle i's springs (SumBlocksAt, as pass 2 above),
// in double, then rounded to float into rest_soa; the bodies no spring reaches keep D.
void FamilyRestDiagonal(const SpringLayout& layout, const double* HWY_RESTRICT ux,
                        const double* HWY_RESTRICT uy, const double* HWY_RESTRICT uz,
                        const double* HWY_RESTRICT alpha, const double* HWY_RESTRICT beta,
                        const double* HWY_RESTRICT diag_soa, std::size_t bodies, float* HWY_RESTRICT rest_soa) {
  const D d;
  const hn::Rebind<float, D> df;
  const std::size_t N = hn::Lanes(d);
  const std::size_t P = static_cast<std::size_t>(layout.num_particles);
  HWY_ALIGN double tail[kSpringLanePad] = {};
  HWY_ALIGN float rounded[kSpringLanePad];
  for (std::size_t p = 0; p < P; p += N) {
    const std::size_t lanes = std::min(N, P - p);
    V sum[6];
    SumBlocksAt(layout, p, ux, uy, uz, alpha, beta, sum);
    for (int e = 0; e < 6; ++e) {
      const double* D_at = diag_soa + e * bodies + p;
      if (lanes < N) D_at = std::copy(D_at, D_at + lanes, tail) - lanes;  // (the soa's next entry follows)
      const auto R = hn::DemoteTo(df, hn::Add(hn::LoadU(d, D_at), sum[e]));
      if (lanes == N) {
        hn::StoreU(R, df, rest_soa + e * bodies + p);
      } else {
        hn::StoreU(R, df, rounded);
        std::copy(rounded, rounded + lanes, rest_soa + e * bodies + p);
      }
    }
  }
  for (std::size_t i = P; i < bodies; ++i)
    for (int e = 0; e < 6; ++e) rest_soa[e * bodies + i] = static_cast<float>(diag_soa[e * bodies + i]);
}

// to[i] = from[i] rounded to float, i < n.
void DemoteToFloat(const double* HWY_RESTRICT from, std::size_t n, float* HWY_RESTRICT to) {
  const D d;
  const hn::Rebind<float, D> df;
  const std::size_t N = hn::Lanes(d);
  std::size_t i = 0;
  for (; i + N <= n; i += N) hn::StoreU(hn::DemoteTo(df, hn::LoadU(d, from + i)), df, to + i);
  for (; i < n; ++i) to[i] = static_cast<float>(from[i]);
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(FamilyAssemble);
HWY_EXPORT(FamilyRestDiagonal);
HWY_EXPORT(DemoteToFloat);

namespace {

// R at the movable ends of the springs to immovable bodies (`filtered`, their numbers not yet
// zeroed): M + h c I less those springs' blocks, which the mat-vec does not apply, summed in
// double in (particle, slot) order, then rounded. Pass 2 wrote M + h c I there.
void rest_less_filtered(const SpringLayout& layout, const Eigen::VectorXd& inv_mass, const FamilyHessian& out,
                        const std::vector<std::int32_t>& filtered) {
  thread_local std::vector<std::pair<std::int32_t, std::int32_t>> ends;  // (particle, slot)
  ends.clear();
  for (const std::int32_t s : filtered) {
    const std::size_t slot = static_cast<std::size_t>(s);
    for (const SpringFamily& fam : layout.families) {
      if (slot < fam.slot_first || slot >= fam.slot_first + fam.rest.size()) continue;
      const std::int32_t a = fam.first + static_cast<std::int32_t>(slot - fam.slot_first);
      for (const std::int32_t i : {a, a + fam.offset})
        if (inv_mass[i] != 0.0) ends.emplace_back(i, s);
      break;
    }
  }
  std::sort(ends.begin(), ends.end());
  for (std::size_t j = 0; j < ends.size();) {
    const std::int32_t i = ends[j].first;
    Mat3 R = (1.0 / inv_mass[i] + out.drag_h * out.drag) * Mat3::Identity();  // pass 2's M + h c I
    for (; j < ends.size() && ends[j].first == i; ++j) {
      const std::int32_t s = ends[j].second;
      subtract_block(R, out.alpha[s], out.beta[s], Vec3(out.ux[s], out.uy[s], out.uz[s]));
    }
    const double r[6] = {R(0, 0), R(1, 1), R(2, 2), R(0, 1), R(0, 2), R(1, 2)};  // as rest_soa
    float* at = out.rest_soa + static_cast<std::size_t>(i);
    for (int e = 0; e < 6; ++e) at[static_cast<std::size_t>(e) * out.bodies] = static_cast<float>(r[e]);
  }
}

}  // namespace

std::size_t family_assemble(const SpringLayout& layout, const Eigen::Matrix3Xd& y,
                            const Eigen::VectorXd& inv_mass, const double* start_length,
                            const FamilyHessian& out) {
  // Scratch per thread (compare runs lanes on threads), grown, never shrunk: the window's 4
  // arrays (y, the inverse masses) of about kWindowBlock + 2 nx particles.
  thread_local hwy::AlignedFreeUniquePtr<double[]> scratch;
  thread_local std::size_t capacity = 0;
  thread_local std::vector<std::int32_t> filtered;  // slots of springs at an immovable body
  const std::size_t stride = window_stride(layout);
  if (4 * stride > capacity) {
    capacity = 4 * stride;
    scratch = hwy::AllocateAligned<double>(capacity);
  }
  const std::size_t written = HWY_DYNAMIC_DISPATCH(FamilyAssemble)(layout, y.data(), inv_mass.data(), start_length,
                                                                   out, filtered, scratch.get(), stride);
  if (out.rest_soa) rest_less_filtered(layout, inv_mass, out, filtered);
  for (const std::int32_t s : filtered)  // their rows and columns removed
    out.alpha[s] = out.beta[s] = out.alpha_projected[s] = out.beta_projected[s] = 0.0;
  return written;
}

void family_rest_diagonal(const SpringLayout& layout, const double* ux, const double* uy, const double* uz,
                          const double* alpha, const double* beta, const double* diag_soa, std::size_t bodies,
                          float* rest_soa) {
  HWY_DYNAMIC_DISPATCH(FamilyRestDiagonal)(layout, ux, uy, uz, alpha, beta, diag_soa, bodies, rest_soa);
}

void demote_to_float(const double* from, std::size_t n, float* to) {
  HWY_DYNAMIC_DISPATCH(DemoteToFloat)(from, n, to);
}

}  // namespace clothsim
#endif  // HWY_ONCE
