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

#ifndef CLOTHSIM_XPBD_SWEEP_ARRAYS
#define CLOTHSIM_XPBD_SWEEP_ARRAYS
namespace clothsim {

// The arrays one sweep reads: components c[k] of y and s[k] of the start positions (stride
// apart), the family's rest lengths, gains and multipliers by position, the inverse masses.
struct SweepArrays {
  double* c[3];
  const double* s[3];
  const double* rest;
  const double* gain;
  double* lambda;
  const double* w;
};

}  // namespace clothsim
#endif

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

// The family's constants for one step: alpha~^-1 = ks h^2, kd h, and their sum.
struct FamilyStep {
  V cs, kdh, both;
};

HWY_INLINE FamilyStep StepOf(const SpringFamily& fam, double h) {
  const D d;
  return {hn::Set(d, fam.ks * h * h), hn::Set(d, fam.kd * h), hn::Set(d, fam.ks * h * h + fam.kd * h)};
}

// The projection of a vector of springs (xpbd_kernels.h's formula) from their ends, start
// separations, rest lengths, multipliers and gains 1 / denominator: the multipliers' change
// (0 where no spring acts or `live` is clear) and t = dlambda / l, so an end moves by
// w t (y_a - y_b). With u = d / l, the damper's rate u . (d - gap) is l - d . gap / l, so
//     dlambda = g (cs l0 - lambda - (cs + kd h) l + kd h (d . gap) / l).
template <class M>
HWY_INLINE V Project(const V dd[3], const V gap[3], V l0, V lam, V g, M live, const FamilyStep& k, V& t) {
  const D d;
  const V zero = hn::Zero(d);
  const V l2 = hn::Add(hn::Add(hn::Mul(dd[0], dd[0]), hn::Mul(dd[1], dd[1])), hn::Mul(dd[2], dd[2]));
  const V dg = hn::Add(hn::Add(hn::Mul(dd[0], gap[0]), hn::Mul(dd[1], gap[1])), hn::Mul(dd[2], gap[2]));
  const V l = hn::Sqrt(l2);
  const auto acts = hn::And(live, hn::AndNot(hn::Le(l, zero), hn::Gt(g, zero)));
  const V inv_l = hn::IfThenElseZero(acts, hn::Div(hn::Set(d, 1.0), l));
  const V numerator = hn::Add(hn::Sub(hn::Sub(hn::Mul(k.cs, l0), lam), hn::Mul(k.both, l)),
                              hn::Mul(k.kdh, hn::Mul(dg, inv_l)));
  const V dlam = hn::IfThenElseZero(acts, hn::Mul(numerator, g));
  t = hn::Mul(dlam, inv_l);
  return dlam;
}

// One set of a column-wise family: each run's positions a vector at a time, lanes past the
// run masked. The ends at b are re-read after the stores at a, so a masked lane (adding 0)
// never writes back a value another lane has just moved.
void ProjectSet(const SpringFamily& fam, const SweepArrays& in, const std::pair<std::size_t, std::size_t>* runs,
                std::size_t num_runs, double h) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const FamilyStep k = StepOf(fam, h);
  const std::size_t off = static_cast<std::size_t>(fam.offset);
  for (std::size_t r = 0; r < num_runs; ++r) {
    for (std::size_t q = runs[r].first; q < runs[r].second; q += N) {
      const std::size_t a = static_cast<std::size_t>(fam.first) + q, b = a + off;
      V ya[3], dd[3], gap[3], t;
      for (int c = 0; c < 3; ++c) {
        ya[c] = hn::LoadU(d, in.c[c] + a);
        dd[c] = hn::Sub(ya[c], hn::LoadU(d, in.c[c] + b));
        gap[c] = hn::Sub(hn::LoadU(d, in.s[c] + a), hn::LoadU(d, in.s[c] + b));
      }
      const V lam = hn::LoadU(d, in.lambda + q);
      const V dlam = Project(dd, gap, hn::LoadU(d, in.rest + q), lam, hn::LoadU(d, in.gain + q),
                             hn::FirstN(d, runs[r].second - q), k, t);
      hn::StoreU(hn::Add(lam, dlam), d, in.lambda + q);
      const V ta = hn::Mul(hn::LoadU(d, in.w + a), t), tb = hn::Mul(hn::LoadU(d, in.w + b), t);
      for (int c = 0; c < 3; ++c) hn::StoreU(hn::Add(ya[c], hn::Mul(ta, dd[c])), d, in.c[c] + a);
      for (int c = 0; c < 3; ++c) hn::StoreU(hn::Sub(hn::LoadU(d, in.c[c] + b), hn::Mul(tb, dd[c])), d, in.c[c] + b);
    }
  }
}

// 2L consecutive values from `at` split into every other lane (di = 1: lanes 0, 2, 4... and
// 1, 3, 5...) or every other pair of lanes (di = 2: lanes 0, 1, 4, 5... and 2, 3, 6, 7...),
// and stored back. Pairs: a vector of two lanes is one pair; of four, two, whose halves Concat
// joins; of eight, four, gathered into halves by one in-vector permutation (its own inverse).
template <int kDi>
struct Split {
  static HWY_INLINE void Load(const double* HWY_RESTRICT at, V& a, V& b) {
    const D d;
    if constexpr (kDi == 1) {
      hn::LoadInterleaved2(d, at, a, b);
    } else if constexpr (hn::MaxLanes(D()) == 2) {
      a = hn::LoadU(d, at), b = hn::LoadU(d, at + 2);
    } else {
#if HWY_TARGET != HWY_SCALAR
      const V v0 = Pairs(hn::LoadU(d, at)), v1 = Pairs(hn::LoadU(d, at + hn::Lanes(d)));
      a = hn::ConcatLowerLower(d, v1, v0), b = hn::ConcatUpperUpper(d, v1, v0);
#endif
    }
  }
  static HWY_INLINE void Store(V a, V b, double* HWY_RESTRICT at) {
    const D d;
    if constexpr (kDi == 1) {
      hn::StoreInterleaved2(a, b, d, at);
    } else if constexpr (hn::MaxLanes(D()) == 2) {
      hn::StoreU(a, d, at), hn::StoreU(b, d, at + 2);
    } else {
#if HWY_TARGET != HWY_SCALAR
      hn::StoreU(Pairs(hn::ConcatLowerLower(d, b, a)), d, at);
      hn::StoreU(Pairs(hn::ConcatUpperUpper(d, b, a)), d, at + hn::Lanes(d));
#endif
    }
  }
  // Lanes 0, 1, 4, 5 | 2, 3, 6, 7 of eight; four or fewer are already in halves.
  static HWY_INLINE V Pairs(V v) {
    if constexpr (hn::MaxLanes(D()) == 8) {
      const D d;
      alignas(64) static constexpr std::int64_t kIdx[8] = {0, 1, 4, 5, 2, 3, 6, 7};
      return hn::TableLookupLanes(v, hn::SetTableIndices(d, kIdx));
    } else {
      return v;
    }
  }
};

// One set of a row-wise family with di = 1 or 2: its springs join p and p + di for the p of
// every other run of di, so the 2L particles from p on hold L springs whose a ends Split takes
// apart from their b ends, and 2L positions from q hold those L springs' positions.
// `q0`: the set's first position (its particle's offset within a run of 2 di even).
template <int kDi>
void ProjectRowSet(const SpringFamily& fam, const SweepArrays& in, std::size_t q0, double h) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const FamilyStep k = StepOf(fam, h);
  const auto all = hn::FirstN(d, N);
  using S = Split<kDi>;
  for (std::size_t q = q0; q < static_cast<std::size_t>(fam.count); q += 2 * N) {
    const std::size_t a = static_cast<std::size_t>(fam.first) + q;
    V ya[3], yb[3], dd[3], gap[3], xa, xb, l0, g, lam, other, skip, t;
    for (int c = 0; c < 3; ++c) {
      S::Load(in.c[c] + a, ya[c], yb[c]);
      S::Load(in.s[c] + a, xa, xb);
      dd[c] = hn::Sub(ya[c], yb[c]), gap[c] = hn::Sub(xa, xb);
    }
    S::Load(in.rest + q, l0, skip);
    S::Load(in.gain + q, g, skip);
    S::Load(in.lambda + q, lam, other);
    S::Load(in.w + a, xa, xb);  // the ends' inverse masses
    const V dlam = Project(dd, gap, l0, lam, g, all, k, t);
    S::Store(hn::Add(lam, dlam), other, in.lambda + q);
    const V ta = hn::Mul(xa, t), tb = hn::Mul(xb, t);
    for (int c = 0; c < 3; ++c) S::Store(hn::Add(ya[c], hn::Mul(ta, dd[c])), hn::Sub(yb[c], hn::Mul(tb, dd[c])), in.c[c] + a);
  }
}

// The set's kernel: by lanes or pairs from q0 for a row-wise family with di = 1 or 2 (a
// vector of one lane holds no pair: then by runs, as for the other families), else by runs.
void ProjectFamilySet(const SpringFamily& fam, const SweepArrays& in, const std::pair<std::size_t, std::size_t>* runs,
                      std::size_t num_runs, long q0, double h) {
  if (q0 >= 0 && fam.di == 1) return ProjectRowSet<1>(fam, in, static_cast<std::size_t>(q0), h);
#if HWY_TARGET != HWY_SCALAR
  if (q0 >= 0 && fam.di == 2) return ProjectRowSet<2>(fam, in, static_cast<std::size_t>(q0), h);
#endif
  ProjectSet(fam, in, runs, num_runs, h);
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(ProjectFamilySet);

namespace {

// The grid's row length, read off a family that crosses rows (0 when none does: then no
// family needs it).
int row_length(const SpringLayout& layout) {
  for (const SpringFamily& fam : layout.families)
    if (fam.dj != 0) return (fam.offset - fam.di) / fam.dj;
  return 0;
}

// Positions a family's per-position arrays hold: its count and two vectors' worth past it,
// all a set's last 2L-wide load or store can reach.
std::size_t padded_positions(const SpringFamily& fam) {
  return static_cast<std::size_t>(fam.count) + 2 * static_cast<std::size_t>(kSpringLanePad);
}

// Which of the family's two independent sets the spring at particle a belongs to.
int set_of(const SpringFamily& fam, int a, int nx) {
  return fam.dj == 0 ? (a / fam.di) & 1 : ((a / nx) / fam.dj) & 1;
}

// Each set's runs of consecutive positions (rows of a column-wise family).
void build_sets(const Model& model, XpbdFamilies& f) {
  const SpringLayout& layout = model.spring_layout;
  const int nx = row_length(layout);
  f.runs.clear();
  for (const SpringFamily& fam : layout.families) {
    for (int set = 0; set < 2; ++set) {
      std::vector<std::pair<std::size_t, std::size_t>> runs;
      for (std::size_t k = 0; k < static_cast<std::size_t>(fam.count); ++k) {
        if (set_of(fam, fam.first + static_cast<int>(k), nx) != set) continue;
        if (!runs.empty() && runs.back().second == k) ++runs.back().second;
        else runs.emplace_back(k, k + 1);
      }
      f.runs.push_back(std::move(runs));
    }
  }
  f.stride = (static_cast<std::size_t>(layout.num_particles) + kSpringLanePad + 7) / 8 * 8;
  f.rest.clear();
  for (const SpringFamily& fam : layout.families) {
    std::vector<double> rest(padded_positions(fam), 0.0);
    std::copy(fam.rest.begin(), fam.rest.end(), rest.begin());
    f.rest.push_back(std::move(rest));
  }
  f.model = &model;
  f.springs = model.springs.size();
}

// Per family and position, 1 / ((ks h^2 + kd h)(w_a + w_b) + 1), the projection's denominator
// (xpbd_kernels.h); 0 where the family has no spring, or where both ends are immovable.
void build_gains(const Model& model, double h, XpbdFamilies& f) {
  const auto& families = model.spring_layout.families;
  f.gain.resize(families.size());
  for (std::size_t k = 0; k < families.size(); ++k) {
    const SpringFamily& fam = families[k];
    const double scale = fam.ks * h * h + fam.kd * h;
    f.gain[k].assign(padded_positions(fam), 0.0);
    for (std::size_t q = 0; q < static_cast<std::size_t>(fam.count); ++q) {
      const std::size_t a = static_cast<std::size_t>(fam.first) + q;
      const double w = f.w[a] + f.w[a + static_cast<std::size_t>(fam.offset)];
      if (fam.rest[q] > 0.0 && w != 0.0) f.gain[k][q] = 1.0 / (scale * w + 1.0);
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
  to_soa(p.start, P, f.stride, f.x);
  const auto& families = model.spring_layout.families;
  f.lambda.resize(families.size());
  for (std::size_t k = 0; k < families.size(); ++k) f.lambda[k].assign(padded_positions(families[k]), 0.0);
}

// The set's first position in a row-wise family: its particle p has floor(p / di) mod 2 =
// set, and p mod di = 0 (-1 when the family's first particle is off that grid of runs).
static long row_set_start(const SpringFamily& fam, std::size_t set) {
  const long di = fam.di, first = fam.first;
  if (first % di != 0) return -1;
  return ((first / di) & 1) == static_cast<long>(set) ? 0 : di;
}

void xpbd_family_sweep(const Model& model, double h, XpbdFamilies& f) {
  const auto& families = model.spring_layout.families;
  const std::size_t st = f.stride;
  for (std::size_t k = 0; k < families.size(); ++k)
    for (std::size_t set = 0; set < 2; ++set) {
      const SpringFamily& fam = families[k];
      const SweepArrays in{{f.y.data(), f.y.data() + st, f.y.data() + 2 * st},
                           {f.x.data(), f.x.data() + st, f.x.data() + 2 * st},
                           f.rest[k].data(), f.gain[k].data(), f.lambda[k].data(), f.w.data()};
      const long q0 = fam.dj == 0 && (fam.di == 1 || fam.di == 2) ? row_set_start(fam, set) : -1;
      const auto& runs = f.runs[2 * k + set];
      HWY_DYNAMIC_DISPATCH(ProjectFamilySet)(fam, in, runs.data(), runs.size(), q0, h);
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
