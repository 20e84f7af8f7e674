#include "vbd_kernels.h"

#include <algorithm>
#include <cmath>

#include "core/model/barrier_contacts.h"

namespace clothsim {
namespace {

void build_incidence(const Model& model, VbdGraph& g) {
  const int B = model.num_bodies();
  const Springs& s = model.springs;
  g.start.assign(B + 1, 0);
  for (std::size_t k = 0; k < s.size(); ++k) ++g.start[s.a[k] + 1], ++g.start[s.b[k] + 1];
  for (int i = 0; i < B; ++i) g.start[i + 1] += g.start[i];
  g.spring.assign(g.start[B], 0);
  g.neighbour.assign(g.start[B], 0);
  std::vector<std::int32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t k = 0; k < s.size(); ++k) {
    g.neighbour[fill[s.a[k]]] = s.b[k];
    g.spring[fill[s.a[k]]++] = static_cast<std::int32_t>(k);
    g.neighbour[fill[s.b[k]]] = s.a[k];
    g.spring[fill[s.b[k]]++] = static_cast<std::int32_t>(k);
  }
}

// Greedy, in body order: each body takes the smallest colour none of its neighbours has.
void colour_greedily(const Model& model, VbdGraph& g) {
  const int B = model.num_bodies();
  std::vector<int> colour(B, -1);
  std::vector<char> taken;
  for (int i = 0; i < B; ++i) {
    taken.assign(taken.size(), 0);
    for (int e = g.start[i]; e < g.start[i + 1]; ++e) {
      const int c = colour[g.neighbour[e]];
      if (c < 0) continue;
      if (c >= static_cast<int>(taken.size())) taken.resize(c + 1, 0);
      taken[c] = 1;
    }
    const int c = static_cast<int>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    colour[i] = c;
    if (c >= static_cast<int>(g.colours.size())) g.colours.resize(c + 1);
    g.colours[c].push_back(i);
  }
}

// A symmetric 3x3 matrix by its six entries (the per-vertex Hessian, accumulated without
// forming 3x3 products).
struct Sym3 {
  double xx, yy, zz, xy, xz, yz;
  void add_outer(double c, const Vec3& d) {
    xx += c * d.x() * d.x(), yy += c * d.y() * d.y(), zz += c * d.z() * d.z();
    xy += c * d.x() * d.y(), xz += c * d.x() * d.z(), yz += c * d.y() * d.z();
  }
  void add_diagonal(double c) { xx += c, yy += c, zz += c; }
  void add(const Eigen::Matrix3d& m) {
    xx += m(0, 0), yy += m(1, 1), zz += m(2, 2), xy += m(0, 1), xz += m(0, 2), yz += m(1, 2);
  }
  // H^-1 b by the adjugate (H is positive definite: a_i I plus PSD terms).
  Vec3 solve(const Vec3& b) const {
    const double cxx = yy * zz - yz * yz, cxy = xz * yz - xy * zz, cxz = xy * yz - xz * yy;
    const double cyy = xx * zz - xz * xz, cyz = xy * xz - xx * yz, czz = xx * yy - xy * xy;
    const double det = xx * cxx + xy * cxy + xz * cxz;
    return Vec3(cxx * b.x() + cxy * b.y() + cxz * b.z(), cxy * b.x() + cyy * b.y() + cyz * b.z(),
                cxz * b.x() + cyz * b.y() + czz * b.z()) / det;
  }
};

// The vertex's gradient f and Hessian H of G with the others held: inertia, its springs
// (each block K = k P + (T/l)(I - P), T/l clamped at 0: spring_force.h's projected
// step_spring_hessian, with T = k (l - blended rest)); contacts are held after the step.
void vertex_system(const StepProblem& p, const VbdGraph& g, const Eigen::Matrix3Xd& y, int i, Vec3& f,
                   Sym3& H) {
  const Vec3 yi = y.col(i);
  f = p.weight[i] * (yi - p.target.col(i));
  H = Sym3{p.weight[i], p.weight[i], p.weight[i], 0.0, 0.0, 0.0};
  for (int e = g.start[i]; e < g.start[i + 1]; ++e) {
    const int k = g.spring[e];
    const Vec3 d = yi - y.col(g.neighbour[e]);
    const double l2 = d.squaredNorm(), l = std::sqrt(l2);
    const double stiffness = p.stiffness[k];
    if (!(l > 0.0)) {  // no direction: the isotropic stand-in
      H.add_diagonal(stiffness);
      continue;
    }
    const double tension_per_length = stiffness * (l - p.rest[k]) / l;
    f += tension_per_length * d;
    const double transverse = std::max(0.0, tension_per_length);
    H.add_outer((stiffness - transverse) / l2, d);
    H.add_diagonal(transverse);
  }
}

// Vertex i's barrier pairs into its system: gradient (its own side of each pair) and Hessian.
void add_vertex_barrier(const VbdBarrier& b, const Eigen::Matrix3Xd& y, int i, Vec3& f, Sym3& H) {
  const Model& model = *b.model;
  const BarrierParams params = barrier_params(model);
  for_each_barrier_pair_of(model, *b.inv_mass, i, [&](const BarrierPair& pair) {
    const StepPairTerms t = step_pair_terms(model, params, pair, *b.start_x, *b.start_x, y, b.h);
    if (!t.active) return;
    f += pair.a == i ? t.gradient : Vec3(-t.gradient);
    H.add(t.hessian);
  });
}

// The largest fraction of vertex i's step that keeps each of its pairs at kVbdBarrierKeep of
// its distance.
double vertex_step_bound(const VbdBarrier& b, const Eigen::Matrix3Xd& y, int i, const Vec3& step) {
  const Model& model = *b.model;
  double alpha = 1.0;
  for_each_barrier_pair_of(model, *b.inv_mass, i, [&](const BarrierPair& pair) {
    const Vec3 move = pair.a == i ? step : Vec3(-step);
    if (pair.b < 0)
      alpha = std::min(alpha, plane_step_bound(y(1, pair.a) - model.ground.height - pair.r, move.y(), kVbdBarrierKeep));
    else
      alpha = std::min(alpha, sphere_step_bound(y.col(pair.a) - y.col(pair.b), move, pair.r, kVbdBarrierKeep));
  });
  return alpha;
}

bool inside_a_reach(const Colliders& c, const Vec3& y) {
  bool inside = false;
  for_each_penetration(c, y, [&](const Penetration&) { inside = true; });
  return inside;
}

}  // namespace

void build_vbd_graph(const Model& model, VbdGraph& g) {
  if (g.model == &model && g.springs == model.springs.size()) return;
  g = VbdGraph{};
  build_incidence(model, g);
  colour_greedily(model, g);
  g.model = &model;
  g.springs = model.springs.size();
}

void vbd_initial_guess(const Model& model, const StepProblem& p, const State& state,
                       const Eigen::Matrix3Xd& acceleration, Eigen::Matrix3Xd& y) {
  const double g = model.gravity.norm();
  const Vec3 down = g > 0.0 ? Vec3(model.gravity / g) : Vec3(Vec3::Zero());
  y = p.target;
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (p.weight[i] == 0.0) continue;
    const double along = g > 0.0 ? std::clamp(acceleration.col(i).dot(down), 0.0, g) : 0.0;
    y.col(i) = state.x.col(i) + p.h * state.v.col(i) + (p.h * p.h * along) * down;
  }
}

void vbd_hold(const Colliders& colliders, const Vec3& from, const double H[6], Vec3& y, VbdContact& c) {
  if (!c.held && !inside_a_reach(colliders, y)) return;
  if (!c.planed) held_plane(colliders, from, y, c.normal, c.plane), c.planed = 1;
  const double below = c.plane - c.normal.dot(y);
  c.held = below > 0.0;
  if (!c.held) return;
  const Sym3 h{H[0], H[1], H[2], H[3], H[4], H[5]};
  const Vec3 w = h.solve(c.normal);
  const double curvature = c.normal.dot(w);
  y += (below / curvature) * w;
  y += (c.plane - c.normal.dot(y)) * c.normal;  // rounding: exactly on the plane
}

void vbd_sweep(const StepProblem& p, const VbdGraph& g, Eigen::Matrix3Xd& y, std::vector<VbdContact>& contacts,
               int first_body, const VbdBarrier* barrier) {
  const bool colliders = !barrier && (p.colliders.ground || !p.colliders.centre.empty());
  Vec3 f;
  Sym3 H;
  for (const std::vector<std::int32_t>& colour : g.colours)
    for (std::int32_t i : colour) {
      if (i < first_body || p.weight[i] == 0.0) continue;
      vertex_system(p, g, y, i, f, H);
      if (barrier) add_vertex_barrier(*barrier, y, i, f, H);
      Vec3 step = H.solve(-f);
      if (!step.allFinite()) continue;
      if (barrier) step *= vertex_step_bound(*barrier, y, i, step);
      Vec3 yi = y.col(i) + step;
      const double entries[6] = {H.xx, H.yy, H.zz, H.xy, H.xz, H.yz};
      if (colliders && i < static_cast<std::int32_t>(contacts.size())) vbd_hold(p.colliders, p.start.col(i), entries, yi, contacts[i]);
      y.col(i) = yi;
    }
}

}  // namespace clothsim
