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

// One set of one family: for each run, vectors of positions projected at once. The ends
// at b are re-read after the stores at a, so a lane outside the set (adding 0) never writes
// back a value another lane has just moved.
void ProjectSet(const SpringFamily& fam, const double* HWY_RESTRICT rest, const double* HWY_RESTRICT gain,
                const std::pair<std::size_t, std::size_t>* runs, std::size_t num_runs, double h,
                std::size_t stride, double* HWY_RESTRICT y, const double* HWY_RESTRICT gap, std::size_t gap_stride,
                const double* HWY_RESTRICT w, double* HWY_RESTRICT lambda) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const auto cs = hn::Set(d, fam.ks * h * h);  // alpha~^-1
  const auto kdh = hn::Set(d, fam.kd * h);
  double* HWY_RESTRICT c[3] = {y, y + stride, y + 2 * stride};
  const double* HWY_RESTRICT s[3] = {gap, gap + gap_stride, gap + 2 * gap_stride};  // x_a - x_b
  const std::size_t off = static_cast<std::size_t>(fam.offset);
  for (std::size_t r = 0; r < num_runs; ++r) {
    for (std::size_t q = runs[r].first; q < runs[r].second; q += N) {
      const std::size_t a = static_cast<std::size_t>(fam.first) + q, b = a + off;
      const auto l0 = hn::LoadU(d, rest + q);
      const auto lam = hn::LoadU(d, lambda + q);
      const auto wa = hn::LoadU(d, w + a), wb = hn::LoadU(d, w + b);
      const auto g = hn::LoadU(d, gain + q);
      decltype(hn::Zero(d)) ya[3], yb[3], dd[3];
      for (int k = 0; k < 3; ++k)
        ya[k] = hn::LoadU(d, c[k] + a), yb[k] = hn::LoadU(d, c[k] + b), dd[k] = hn::Sub(ya[k], yb[k]);
      const auto l = hn::Sqrt(hn::Add(hn::Add(hn::Mul(dd[0], dd[0]), hn::Mul(dd[1], dd[1])), hn::Mul(dd[2], dd[2])));
      const auto acts = hn::AndNot(hn::Le(l, zero), hn::Gt(g, zero));
      const auto inv_l = hn::IfThenElseZero(acts, hn::Div(one, l));  // 0: u = 0 where no spring acts
      auto rate = zero;  // grad C . (y - x_n)
      decltype(hn::Zero(d)) u[3];
      for (int k = 0; k < 3; ++k) {
        u[k] = hn::Mul(dd[k], inv_l);
        const auto moved = hn::Sub(dd[k], hn::LoadU(d, s[k] + q));  // (y_a - x_a) - (y_b - x_b)
        rate = hn::Add(rate, hn::Mul(u[k], moved));
      }
      const auto numerator = hn::Sub(hn::Sub(hn::Mul(hn::Neg(cs), hn::Sub(l, l0)), lam), hn::Mul(kdh, rate));
      const auto dlam = hn::IfThenElseZero(acts, hn::Mul(numerator, g));
      hn::StoreU(hn::Add(lam, dlam), d, lambda + q);
      const auto ta = hn::Mul(wa, dlam), tb = hn::Mul(wb, dlam);
      for (int k = 0; k < 3; ++k) hn::StoreU(hn::Add(ya[k], hn::Mul(ta, u[k])), d, c[k] + a);
      for (int k = 0; k < 3; ++k) hn::StoreU(hn::Sub(hn::LoadU(d, c[k] + b), hn::Mul(tb, u[k])), d, c[k] + b);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(ProjectSet);

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
      const auto& runs = f.runs[2 * k + set];
      HWY_DYNAMIC_DISPATCH(ProjectSet)(families[k], f.rest[2 * k + set].data(), f.gain[2 * k + set].data(), runs.data(), runs.size(), h,
                                       f.stride, f.y.data(), f.gap[k].data(), f.lambda[k].size(), f.w.data(),
                                       f.lambda[k].data());
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
