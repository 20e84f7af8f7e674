#include "vbd_kernels.h"

#include <Eigen/Dense>
#include <algorithm>

#include "core/springs/spring_force.h"

namespace clothsim {
namespace {

void build_incidence(const Model& model, VbdGraph& g) {
  const int B = model.num_bodies();
  const Springs& s = model.springs;
  g.start.assign(B + 1, 0);
  for (std::size_t k = 0; k < s.size(); ++k) ++g.start[s.a[k] + 1], ++g.start[s.b[k] + 1];
  for (int i = 0; i < B; ++i) g.start[i + 1] += g.start[i];
  g.spring.assign(g.start[B], 0);
  std::vector<std::int32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t k = 0; k < s.size(); ++k) {
    g.spring[fill[s.a[k]]++] = static_cast<std::int32_t>(k);
    g.spring[fill[s.b[k]]++] = static_cast<std::int32_t>(k);
  }
}

int other_end(const Springs& s, int k, int i) { return s.a[k] == i ? s.b[k] : s.a[k]; }

// Greedy, in body order: each body takes the smallest colour none of its neighbours has.
void colour_greedily(const Model& model, VbdGraph& g) {
  const int B = model.num_bodies();
  std::vector<int> colour(B, -1);
  std::vector<char> taken;
  for (int i = 0; i < B; ++i) {
    taken.assign(taken.size(), 0);
    for (int e = g.start[i]; e < g.start[i + 1]; ++e) {
      const int c = colour[other_end(model.springs, g.spring[e], i)];
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

// The vertex's gradient f and Hessian H of G with the others held: inertia, its springs
// (Hessian blocks projected PSD, spring_force.h) and the contact penalties.
void vertex_system(const Model& model, const StepProblem& p, const VbdGraph& g,
                   const Eigen::Matrix3Xd& y, int i, Vec3& f, Mat3& H) {
  const Springs& s = model.springs;
  const Vec3 yi = y.col(i);
  f = p.weight[i] * (yi - p.target.col(i));
  H = p.weight[i] * Mat3::Identity();
  for (int e = g.start[i]; e < g.start[i + 1]; ++e) {
    const int k = g.spring[e];
    const Vec3 d = yi - y.col(other_end(s, k, i));
    const double l = d.norm();
    if (l > 0.0) f += (p.stiffness[k] * (l - p.rest[k]) / l) * d;
    H += step_spring_hessian(d, s.rest[k], p.start_length[k], s.ks[k], s.kd[k], p.h, true);
  }
  const double kc = kVbdContactStiffness * p.weight[i];
  for_each_penetration(p.colliders, yi, [&](const Penetration& c) {
    f -= (kc * c.depth) * c.normal;
    H += kc * (c.normal * c.normal.transpose());
  });
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

void vbd_sweep(const Model& model, const StepProblem& p, const VbdGraph& g, Eigen::Matrix3Xd& y) {
  Vec3 f;
  Mat3 H;
  for (const std::vector<std::int32_t>& colour : g.colours)
    for (std::int32_t i : colour) {
      if (p.weight[i] == 0.0) continue;
      vertex_system(model, p, g, y, i, f, H);
      const Vec3 step = H.ldlt().solve(-f);
      if (step.allFinite()) y.col(i) += step;
    }
}

}  // namespace clothsim
