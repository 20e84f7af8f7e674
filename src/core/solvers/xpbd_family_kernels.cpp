// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/xpbd_family_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

#include "contact_scan_kernels.h"
#include "xpbd_family_kernels.h"
#include "xpbd_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;

using V = hn::Vec<D>;

// The projection of a vector of springs (xpbd_kernels.h's formula): their multipliers' change
// (0 where no spring acts) and unit directions u, from the ends, the rest lengths, multipliers,
// gains 1 / denominator and start separations.
HWY_INLINE V Project(const V ya[3], const V yb[3], V l0, V lam, V g, const V gap[3], V cs, V kdh, V u[3]) {
  const D d;
  const V zero = hn::Zero(d);
  V dd[3];
  for (int k = 0; k < 3; ++k) dd[k] = hn::Sub(ya[k], yb[k]);
  const V l = hn::Sqrt(hn::Add(hn::Add(hn::Mul(dd[0], dd[0]), hn::Mul(dd[1], dd[1])), hn::Mul(dd[2], dd[2])));
  const auto acts = hn::AndNot(hn::Le(l, zero), hn::Gt(g, zero));
  const V inv_l = hn::IfThenElseZero(acts, hn::Div(hn::Set(d, 1.0), l));  // 0: u = 0 where no spring acts
  V rate = zero;  // grad C . (y - x_n) = u . ((y_a - y_b) - (x_a - x_b))
  for (int k = 0; k < 3; ++k) {
    u[k] = hn::Mul(dd[k], inv_l);
    rate = hn::Add(rate, hn::Mul(u[k], hn::Sub(dd[k], gap[k])));
  }
  const V numerator = hn::Sub(hn::Sub(hn::Mul(hn::Neg(cs), hn::Sub(l, l0)), lam), hn::Mul(kdh, rate));
  return hn::IfThenElseZero(acts, hn::Mul(numerator, g));
}

// One set of one family: for each run, vectors of positions projected at once. The ends
// at b are re-read after the stores at a, so a lane outside the set (adding 0) never writes
// back a value another lane has just moved.
void ProjectSet(const SpringFamily& fam, const double* HWY_RESTRICT rest, const double* HWY_RESTRICT gain,
                const std::pair<std::size_t, std::size_t>* runs, std::size_t num_runs, double h,
                std::size_t stride, double* HWY_RESTRICT y, const double* HWY_RESTRICT gap, std::size_t gap_stride,
                const double* HWY_RESTRICT w, double* HWY_RESTRICT lambda) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V cs = hn::Set(d, fam.ks * h * h), kdh = hn::Set(d, fam.kd * h);  // alpha~^-1, kd h
  double* HWY_RESTRICT c[3] = {y, y + stride, y + 2 * stride};
  const double* HWY_RESTRICT s[3] = {gap, gap + gap_stride, gap + 2 * gap_stride};
  const std::size_t off = static_cast<std::size_t>(fam.offset);
  for (std::size_t r = 0; r < num_runs; ++r) {
    for (std::size_t q = runs[r].first; q < runs[r].second; q += N) {
      const std::size_t a = static_cast<std::size_t>(fam.first) + q, b = a + off;
      V ya[3], yb[3], gq[3], u[3];
      for (int k = 0; k < 3; ++k)
        ya[k] = hn::LoadU(d, c[k] + a), yb[k] = hn::LoadU(d, c[k] + b), gq[k] = hn::LoadU(d, s[k] + q);
      const V lam = hn::LoadU(d, lambda + q);
      const V dlam = Project(ya, yb, hn::LoadU(d, rest + q), lam, hn::LoadU(d, gain + q), gq, cs, kdh, u);
      hn::StoreU(hn::Add(lam, dlam), d, lambda + q);
      const V ta = hn::Mul(hn::LoadU(d, w + a), dlam), tb = hn::Mul(hn::LoadU(d, w + b), dlam);
      for (int k = 0; k < 3; ++k) hn::StoreU(hn::Add(ya[k], hn::Mul(ta, u[k])), d, c[k] + a);
      for (int k = 0; k < 3; ++k) hn::StoreU(hn::Sub(hn::LoadU(d, c[k] + b), hn::Mul(tb, u[k])), d, c[k] + b);
    }
  }
}

// A set of the row-wise family (i, j) -> (i + 1, j): its springs join p, p + 1 for every p of
// one parity, so a vector of 2L consecutive particles, deinterleaved, is L springs' a ends and
// their b ends, and a vector of 2L positions is L of the set's positions: no lane is masked
// for being outside the set. `q0`: the set's first position.
void ProjectPairs(const SpringFamily& fam, const double* HWY_RESTRICT rest, const double* HWY_RESTRICT gain,
                  std::size_t q0, double h, std::size_t stride, double* HWY_RESTRICT y,
                  const double* HWY_RESTRICT gap, std::size_t gap_stride, const double* HWY_RESTRICT w,
                  double* HWY_RESTRICT lambda) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const V cs = hn::Set(d, fam.ks * h * h), kdh = hn::Set(d, fam.kd * h);
  double* HWY_RESTRICT c[3] = {y, y + stride, y + 2 * stride};
  const double* HWY_RESTRICT s[3] = {gap, gap + gap_stride, gap + 2 * gap_stride};
  V skip;  // the other set's half of a pair of vectors
  for (std::size_t q = q0; q < static_cast<std::size_t>(fam.count); q += 2 * N) {
    const std::size_t a = static_cast<std::size_t>(fam.first) + q;
    V ya[3], yb[3], gq[3], u[3], l0, g, lam, other, wa, wb;
    for (int k = 0; k < 3; ++k) hn::LoadInterleaved2(d, c[k] + a, ya[k], yb[k]), hn::LoadInterleaved2(d, s[k] + q, gq[k], skip);
    hn::LoadInterleaved2(d, rest + q, l0, skip);
    hn::LoadInterleaved2(d, gain + q, g, skip);
    hn::LoadInterleaved2(d, lambda + q, lam, other);
    hn::LoadInterleaved2(d, w + a, wa, wb);
    const V dlam = Project(ya, yb, l0, lam, g, gq, cs, kdh, u);
    hn::StoreInterleaved2(hn::Add(lam, dlam), other, d, lambda + q);
    const V ta = hn::Mul(wa, dlam), tb = hn::Mul(wb, dlam);
    for (int k = 0; k < 3; ++k)
      hn::StoreInterleaved2(hn::Add(ya[k], hn::Mul(ta, u[k])), hn::Sub(yb[k], hn::Mul(tb, u[k])), d, c[k] + a);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(ProjectSet);
HWY_EXPORT(ProjectPairs);

namespace {

// The grid's row length, read off a family that crosses rows (0 when none does: then no
// family needs it).
int row_length(const SpringLayout& layout) {
  for (const SpringFamily& fam : layout.families)
    if (fam.dj != 0) return (fam.offset - fam.di) / fam.dj;
  return 0;
}

// Which of the family's two independent sets the spring at particle a belongs to.
int set_of(const SpringFamily& fam, int a, int nx) {
  return fam.dj == 0 ? (a / fam.di) & 1 : ((a / nx) / fam.dj) & 1;
}

void build_sets(const Model& model, XpbdFamilies& f) {
  const SpringLayout& layout = model.spring_layout;
  const int nx = row_length(layout);
  f.rest.clear();
  f.runs.clear();
  for (const SpringFamily& fam : layout.families) {
    const std::size_t padded = fam.rest.size() + kSpringLanePad;
    for (int set = 0; set < 2; ++set) {
      std::vector<double> rest(padded, 0.0);
      std::vector<std::pair<std::size_t, std::size_t>> runs;
      for (std::size_t k = 0; k < static_cast<std::size_t>(fam.count); ++k) {
        if (set_of(fam, fam.first + static_cast<int>(k), nx) != set) continue;
        rest[k] = fam.rest[k];
        if (fam.dj == 0 && !runs.empty()) runs.back().second = k + 1;  // row-wise: one run, masked
        else if (!runs.empty() && runs.back().second == k) ++runs.back().second;
        else runs.emplace_back(k, k + 1);
      }
      f.rest.push_back(std::move(rest));
      f.runs.push_back(std::move(runs));
    }
  }
  f.stride = (static_cast<std::size_t>(layout.num_particles) + kSpringLanePad + 7) / 8 * 8;
  f.model = &model;
  f.springs = model.springs.size();
}

// Per set and position, 1 / ((ks h^2 + kd h)(w_a + w_b) + 1), the projection's denominator
// (xpbd_kernels.h); 0 where no spring of the set is, or where both ends are immovable.
void build_gains(const Model& model, double h, XpbdFamilies& f) {
  const auto& families = model.spring_layout.families;
  f.gain.resize(f.rest.size());
  for (std::size_t k = 0; k < f.rest.size(); ++k) {
    const SpringFamily& fam = families[k / 2];
    const double scale = fam.ks * h * h + fam.kd * h;
    f.gain[k].assign(f.rest[k].size(), 0.0);
    for (std::size_t q = 0; q < static_cast<std::size_t>(fam.count); ++q) {
      const std::size_t a = static_cast<std::size_t>(fam.first) + q;
      const double w = f.w[a] + f.w[a + static_cast<std::size_t>(fam.offset)];
      if (f.rest[k][q] > 0.0 && w != 0.0) f.gain[k][q] = 1.0 / (scale * w + 1.0);
    }
  }
  f.h = h;
}

void to_soa(const Eigen::Matrix3Xd& m, int n, std::size_t stride, std::vector<double>& out) {
  out.assign(3 * stride, 0.0);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) out[c * stride + i] = m(c, i);
}

}  // namespace

bool xpbd_by_families(const Model& model) {
  const SpringLayout& layout = model.spring_layout;
  return layout.covers(model.springs.size()) && layout.others.size() == 0 &&
         layout.num_particles == model.num_particles;
}

void xpbd_load_families(const Model& model, const StepProblem& p, const Eigen::VectorXd& inv_mass,
                        const Eigen::Matrix3Xd& y, XpbdFamilies& f) {
  if (f.model != &model || f.springs != model.springs.size()) build_sets(model, f), f.w.clear();
  const int P = model.num_particles;
  to_soa(y, P, f.stride, f.y);
  const bool pins_changed = f.w.size() != f.stride || !std::equal(f.w.begin(), f.w.begin() + P, inv_mass.data());
  if (pins_changed) {
    f.w.assign(f.stride, 0.0);
    for (int i = 0; i < P; ++i) f.w[i] = inv_mass[i];
  }
  if (pins_changed || f.h != p.h) build_gains(model, p.h, f);
  const auto& families = model.spring_layout.families;
  f.lambda.resize(families.size());
  f.gap.resize(families.size());
  for (std::size_t k = 0; k < families.size(); ++k) {
    const SpringFamily& fam = families[k];
    const std::size_t len = fam.rest.size() + kSpringLanePad;
    f.lambda[k].assign(len, 0.0);
    f.gap[k].assign(3 * len, 0.0);
    for (std::size_t q = 0; q < static_cast<std::size_t>(fam.count); ++q) {
      const int a = fam.first + static_cast<int>(q), b = a + fam.offset;
      for (std::size_t c = 0; c < 3; ++c) f.gap[k][c * len + q] = p.start(static_cast<Eigen::Index>(c), a) - p.start(static_cast<Eigen::Index>(c), b);
    }
  }
}

void xpbd_family_sweep(const Model& model, double h, XpbdFamilies& f) {
  const auto& families = model.spring_layout.families;
  for (std::size_t k = 0; k < families.size(); ++k)
    for (std::size_t set = 0; set < 2; ++set) {
      const SpringFamily& fam = families[k];
      const std::size_t len = f.lambda[k].size(), at = 2 * k + set;
      if (fam.dj == 0 && fam.di == 1) {  // pairs: the set's positions are those of a's parity `set`
        const std::size_t q0 = (set + static_cast<std::size_t>(fam.first)) & 1;
        HWY_DYNAMIC_DISPATCH(ProjectPairs)(fam, f.rest[at].data(), f.gain[at].data(), q0, h, f.stride, f.y.data(),
                                           f.gap[k].data(), len, f.w.data(), f.lambda[k].data());
        continue;
      }
      const auto& runs = f.runs[at];
      HWY_DYNAMIC_DISPATCH(ProjectSet)(fam, f.rest[at].data(), f.gain[at].data(), runs.data(), runs.size(), h,
                                       f.stride, f.y.data(), f.gap[k].data(), len, f.w.data(), f.lambda[k].data());
    }
}

void xpbd_family_contacts(const Model& model, const StepProblem& p, XpbdFamilies& f) {
  const std::size_t s = f.stride;
  particles_in_reach(p.colliders, f.y.data(), s, static_cast<std::size_t>(model.num_particles), f.touching);
  for (const std::int32_t i : f.touching) {
    if (f.w[i] == 0.0) continue;
    Vec3 yi(f.y[i], f.y[s + i], f.y[2 * s + i]);
    for_each_penetration(p.colliders, yi, [&](const Penetration& c) {
      solve_contact_constraint(yi, p.start.col(i), p.h, c);
    });
    f.y[i] = yi.x(), f.y[s + i] = yi.y(), f.y[2 * s + i] = yi.z();
  }
}

void xpbd_store_families(const XpbdFamilies& f, int particles, Eigen::Matrix3Xd& y) {
  for (int i = 0; i < particles; ++i)
    for (int c = 0; c < 3; ++c) y(c, i) = f.y[c * f.stride + i];
}

}  // namespace clothsim
#endif  // HWY_ONCE
