// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/vbd_grid_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "vbd_grid_kernels.h"
#include "vbd_kernels.h"
#include "in_reach-inl.h"

#ifndef CLOTHSIM_VBD_GRID_ONCE  // this part once, not once per target
#define CLOTHSIM_VBD_GRID_ONCE
namespace clothsim {
namespace {

int floor_div3(int v) { return v >= 0 ? v / 3 : -((2 - v) / 3); }
int mod3(int v) { return v - 3 * floor_div3(v); }

// What a colour's sweep reads: the grid's shape and the step's colour-major arrays.
struct ColourSweep {
  const VbdGrid* g;
  const double* stiffness;  // (12) ks + kd/h of each step's family
  const StepProblem* p;
  VbdGrid* grid;            // the contacts and held flags it writes
  double* y;
  int ci, cj;
};

// vbd_hold for the lanes whose flag is set: lane k is the vertex at colour-major at + k, e its
// Hessian's entries by lane.
void hold_lane(const ColourSweep& w, const double* flag, const double (*e)[16], std::size_t lanes, std::size_t at) {
  VbdGrid& g = *w.grid;
  const std::size_t total = 9 * g.block;
  for (std::size_t k = 0; k < lanes; ++k) {
    if (flag[k] == 0.0) continue;
    const std::size_t v = at + k;
    Vec3 y(g.y[v], g.y[total + v], g.y[2 * total + v]);
    const double H[6] = {e[0][k], e[1][k], e[2][k], e[3][k], e[4][k], e[5][k]};
    vbd_hold(w.p->colliders, w.p->start.col(g.particle[v]), H, y, g.contact[v]);
    g.held[v] = g.contact[v].held;
    g.y[v] = y.x(), g.y[total + v] = y.y(), g.y[2 * total + v] = y.z();
  }
}

}  // namespace
}  // namespace clothsim
#endif

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

struct Sys {  // gradient f and the six entries of the Hessian, per lane
  V fx, fy, fz, xx, yy, zz, xy, xz, yz;
};

HWY_INLINE void AddOuter(Sys& s, V c, V dx, V dy, V dz) {
  s.xx = hn::Add(s.xx, hn::Mul(c, hn::Mul(dx, dx))), s.yy = hn::Add(s.yy, hn::Mul(c, hn::Mul(dy, dy)));
  s.zz = hn::Add(s.zz, hn::Mul(c, hn::Mul(dz, dz))), s.xy = hn::Add(s.xy, hn::Mul(c, hn::Mul(dx, dy)));
  s.xz = hn::Add(s.xz, hn::Mul(c, hn::Mul(dx, dz))), s.yz = hn::Add(s.yz, hn::Mul(c, hn::Mul(dy, dz)));
}

HWY_INLINE void AddDiagonal(Sys& s, V c) { s.xx = hn::Add(s.xx, c), s.yy = hn::Add(s.yy, c), s.zz = hn::Add(s.zz, c); }


// The lanes in `hold` take vbd_hold (vbd_kernels.h) one by one, after the vector's store.
HWY_INLINE void HoldLanes(const ColourSweep& w, const Sys& s, hn::Mask<D> hold, std::size_t at) {
  const D d;
  constexpr std::size_t kMax = HWY_MAX_BYTES / sizeof(double);
  static_assert(kMax <= 16, "hold_lane's lane arrays");
  double flag[16], e[6][16];
  hn::StoreU(hn::IfThenElseZero(hold, hn::Set(d, 1.0)), d, flag);
  const V entries[6] = {s.xx, s.yy, s.zz, s.xy, s.xz, s.yz};
  for (int k = 0; k < 6; ++k) hn::StoreU(entries[k], d, e[k]);
  hold_lane(w, flag, e, hn::Lanes(d), at);
}

// Every vertex of colour (ci, cj), a vector of consecutive ones at a time: its system, then
// its Newton step (by the adjugate), taken where finite and the vertex movable.
void SweepColour(const ColourSweep& w) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const VbdGrid& g = *w.g;
  const std::size_t B = g.block, RW = g.row_width;
  const std::size_t colour = static_cast<std::size_t>(w.ci + 3 * w.cj);
  double* HWY_RESTRICT y[3] = {w.y, w.y + 9 * B, w.y + 18 * B};
  const double* HWY_RESTRICT t[3] = {g.target.data(), g.target.data() + 9 * B, g.target.data() + 18 * B};
  std::ptrdiff_t shift[12];  // from a vertex's index in its block to its neighbour's
  for (std::size_t s = 0; s < g.steps.size(); ++s) {
    const int i = w.ci + g.steps[s].di, j = w.cj + g.steps[s].dj;
    const std::size_t other = static_cast<std::size_t>(mod3(i) + 3 * mod3(j));
    shift[s] = static_cast<std::ptrdiff_t>(other * B) - static_cast<std::ptrdiff_t>(colour * B) +
               static_cast<std::ptrdiff_t>(floor_div3(j) * static_cast<int>(RW) + floor_div3(i));
  }
  const V zero = hn::Zero(d);
  const Colliders& colliders = w.p->colliders;
  const bool any_collider = colliders.ground || !colliders.centre.empty();
  for (int r = 0; r < g.rows; ++r) {
    const std::size_t row = colour * B + static_cast<std::size_t>(r + 1) * RW + 1;
    for (std::size_t m = 0; m < static_cast<std::size_t>(g.columns); m += N) {
      const std::size_t at = row + m;
      const auto in_row = hn::FirstN(d, static_cast<std::size_t>(g.columns) - m);  // not the next row's
      const V a = hn::LoadU(d, g.weight.data() + at);
      const V y0 = hn::LoadU(d, y[0] + at), y1 = hn::LoadU(d, y[1] + at), y2 = hn::LoadU(d, y[2] + at);
      Sys s{hn::Mul(a, hn::Sub(y0, hn::LoadU(d, t[0] + at))), hn::Mul(a, hn::Sub(y1, hn::LoadU(d, t[1] + at))),
            hn::Mul(a, hn::Sub(y2, hn::LoadU(d, t[2] + at))), a, a, a, zero, zero, zero};
      for (std::size_t q = 0; q < g.steps.size(); ++q) {
        const V rest = hn::LoadU(d, g.rest.data() + q * 9 * B + at);
        const auto spring = hn::Ge(rest, zero);
        if (hn::AllFalse(d, spring)) continue;
        const std::size_t o = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(at) + shift[q]);
        const V dx = hn::Sub(y0, hn::LoadU(d, y[0] + o));
        const V dy = hn::Sub(y1, hn::LoadU(d, y[1] + o));
        const V dz = hn::Sub(y2, hn::LoadU(d, y[2] + o));
        const V l2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        const V l = hn::Sqrt(l2);
        const V k = hn::IfThenElseZero(spring, hn::Set(d, w.stiffness[q]));
        const auto apart = hn::Gt(l, zero);
        const V per_length = hn::IfThenElseZero(apart, hn::Div(hn::Mul(k, hn::Sub(l, rest)), l));
        s.fx = hn::Add(s.fx, hn::Mul(per_length, dx)), s.fy = hn::Add(s.fy, hn::Mul(per_length, dy));
        s.fz = hn::Add(s.fz, hn::Mul(per_length, dz));
        const V transverse = hn::IfThenElse(apart, hn::Max(zero, per_length), k);  // apart, or isotropic
        AddOuter(s, hn::IfThenElseZero(apart, hn::Div(hn::Sub(k, transverse), l2)), dx, dy, dz);
        AddDiagonal(s, transverse);
      }
      // step = -H^-1 f by the adjugate (as Sym3::solve)
      const V cxx = hn::Sub(hn::Mul(s.yy, s.zz), hn::Mul(s.yz, s.yz));
      const V cxy = hn::Sub(hn::Mul(s.xz, s.yz), hn::Mul(s.xy, s.zz));
      const V cxz = hn::Sub(hn::Mul(s.xy, s.yz), hn::Mul(s.xz, s.yy));
      const V cyy = hn::Sub(hn::Mul(s.xx, s.zz), hn::Mul(s.xz, s.xz));
      const V cyz = hn::Sub(hn::Mul(s.xy, s.xz), hn::Mul(s.xx, s.yz));
      const V czz = hn::Sub(hn::Mul(s.xx, s.yy), hn::Mul(s.xy, s.xy));
      const V det = hn::Add(hn::Add(hn::Mul(s.xx, cxx), hn::Mul(s.xy, cxy)), hn::Mul(s.xz, cxz));
      const V minus_inv_det = hn::Neg(hn::Div(hn::Set(d, 1.0), det));
      const V sx = hn::Mul(hn::Add(hn::Add(hn::Mul(cxx, s.fx), hn::Mul(cxy, s.fy)), hn::Mul(cxz, s.fz)), minus_inv_det);
      const V sy = hn::Mul(hn::Add(hn::Add(hn::Mul(cxy, s.fx), hn::Mul(cyy, s.fy)), hn::Mul(cyz, s.fz)), minus_inv_det);
      const V sz = hn::Mul(hn::Add(hn::Add(hn::Mul(cxz, s.fx), hn::Mul(cyz, s.fy)), hn::Mul(czz, s.fz)), minus_inv_det);
      const V size = hn::Add(hn::Add(hn::Abs(sx), hn::Abs(sy)), hn::Abs(sz));
      const auto take = hn::And(in_row, hn::And(hn::Gt(a, zero), hn::Lt(size, hn::Set(d, HUGE_VAL))));  // movable, finite
      const V n0 = hn::Add(y0, hn::IfThenElseZero(take, sx)), n1 = hn::Add(y1, hn::IfThenElseZero(take, sy));
      const V n2 = hn::Add(y2, hn::IfThenElseZero(take, sz));
      hn::StoreU(n0, d, y[0] + at), hn::StoreU(n1, d, y[1] + at), hn::StoreU(n2, d, y[2] + at);
      if (!any_collider) continue;
      const auto hold = hn::And(take, hn::Or(InReach(d, colliders, n0, n1, n2), hn::Gt(hn::LoadU(d, g.held.data() + at), zero)));
      if (!hn::AllFalse(d, hold)) HoldLanes(w, s, hold, at);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(SweepColour);

namespace {

void build_grid(const Model& model, VbdGrid& g) {
  const SpringLayout& layout = model.spring_layout;
  g = VbdGrid{};
  g.nx = model.grid_nx, g.ny = model.grid_ny;
  g.columns = (g.nx + 2) / 3, g.rows = (g.ny + 2) / 3;
  g.row_width = static_cast<std::size_t>(g.columns) + 2;
  g.block = (static_cast<std::size_t>(g.rows) + 2) * g.row_width + kSpringLanePad;
  g.index.resize(static_cast<std::size_t>(model.num_particles));
  g.particle.assign(9 * g.block, 0);
  for (int p = 0; p < model.num_particles; ++p) {
    const int i = p % g.nx, j = p / g.nx;
    g.index[p] = static_cast<std::int32_t>(static_cast<std::size_t>(i % 3 + 3 * (j % 3)) * g.block +
                                           static_cast<std::size_t>(j / 3 + 1) * g.row_width + (i / 3 + 1));
    g.particle[g.index[p]] = p;
  }
  for (std::size_t f = 0; f < layout.families.size(); ++f) {
    g.steps.push_back({static_cast<int>(f), layout.families[f].di, layout.families[f].dj});
    g.steps.push_back({static_cast<int>(f), -layout.families[f].di, -layout.families[f].dj});
  }
  g.spring_at.assign(g.steps.size() * 9 * g.block, -1);
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {  // the spring's a sees b one step forwards
    const int a = s.a[k], b = s.b[k];
    const int di = b % g.nx - a % g.nx, dj = b / g.nx - a / g.nx;
    for (std::size_t q = 0; q < g.steps.size(); q += 2)
      if (g.steps[q].di == di && g.steps[q].dj == dj) {
        g.spring_at[q * 9 * g.block + g.index[a]] = static_cast<std::int32_t>(k);
        g.spring_at[(q + 1) * 9 * g.block + g.index[b]] = static_cast<std::int32_t>(k);
      }
  }
  g.model = &model;
  g.springs = s.size();
}

}  // namespace

bool vbd_by_grid(const Model& model) {
  return model.spring_path() == SpringPath::Families && model.grid_nx > 0 &&
         model.grid_nx * model.grid_ny == model.num_particles && model.spring_layout.families.size() <= 6;
}

void vbd_load_grid(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y, VbdGrid& g) {
  if (g.model != &model || g.springs != model.springs.size()) build_grid(model, g);
  const std::size_t total = 9 * g.block;
  g.y.assign(3 * total, 0.0);
  g.target.assign(3 * total, 0.0);
  g.weight.assign(total, 0.0);
  g.held.assign(total, 0.0);
  g.contact.assign(total, VbdContact{});
  for (int i = 0; i < model.num_particles; ++i) {
    const std::size_t at = static_cast<std::size_t>(g.index[i]);
    g.weight[at] = p.weight[i];
    for (std::size_t c = 0; c < 3; ++c) g.y[c * total + at] = y(c, i), g.target[c * total + at] = p.target(c, i);
  }
  g.rest.resize(g.spring_at.size());
  for (std::size_t e = 0; e < g.spring_at.size(); ++e) g.rest[e] = g.spring_at[e] >= 0 ? p.rest[g.spring_at[e]] : -1.0;
}

void vbd_grid_sweep(const Model& model, const StepProblem& p, VbdGrid& g) {
  double stiffness[12];
  const auto& families = model.spring_layout.families;
  for (std::size_t q = 0; q < g.steps.size(); ++q) {
    const SpringFamily& fam = families[g.steps[q].family];
    stiffness[q] = fam.ks + fam.kd / p.h;
  }
  for (int cj = 0; cj < 3; ++cj)
    for (int ci = 0; ci < 3; ++ci)
      HWY_DYNAMIC_DISPATCH(SweepColour)(ColourSweep{&g, stiffness, &p, &g, g.y.data(), ci, cj});
}

void vbd_grid_remember(VbdGrid& g, int k) {
  if (k == 1) g.y_before = g.y;  // y_0, the first guess
  g.y_next = g.y;                // y_{k-1}
}

void vbd_grid_accelerate(VbdGrid& g, int k, double omega) {
  const std::size_t total = 9 * g.block;
  if (k >= 2)
    for (std::size_t v = 0; v < total; ++v) {
      if (!(g.weight[v] > 0.0) || g.contact[v].planed || g.held[v] > 0.0) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t at = c * total + v;
        g.y[at] = omega * (g.y[at] - g.y_before[at]) + g.y_before[at];
      }
    }
  std::swap(g.y_before, g.y_next);  // y_{k-1} is the next sweep's y_{k-2}
}

void vbd_store_grid(const Model& model, const VbdGrid& g, Eigen::Matrix3Xd& y) {
  const std::size_t total = 9 * g.block;
  for (int i = 0; i < model.num_particles; ++i)
    for (std::size_t c = 0; c < 3; ++c) y(c, i) = g.y[c * total + static_cast<std::size_t>(g.index[i])];
}

}  // namespace clothsim
#endif  // HWY_ONCE
