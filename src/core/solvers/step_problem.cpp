#include "step_problem.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/model/collisions.h"
#include "core/implicit/step_contacts.h"

namespace clothsim {

static_assert(kHeldClearance == kContactClearance, "the solvers hold contacts where implicit_euler does");

namespace {

void build_colliders(const Model& model, const State& state, double h, Colliders& c) {
  const double margin = model.collision.margin;
  c = Colliders{};
  c.ground = model.has_ground;
  c.ground_reach = model.ground.height + margin;
  c.ground_friction = model.ground.friction;
  c.ground_restitution = model.ground.restitution;
  for (int s = 0; s < model.num_spheres; ++s) {
    const int body = model.sphere_body(s);
    if (state.inv_mass[body] != 0.0) continue;  // dynamic spheres: the post-step response
    c.centre.push_back(state.x.col(body) + h * state.v.col(body));
    c.velocity.push_back(state.v.col(body));
    c.reach.push_back(model.sphere_radius[s] + margin);
    c.friction.push_back(model.sphere_friction[s]);
    c.restitution.push_back(model.sphere_restitution[s]);
  }
}

void build_body_terms(const Model& model, const State& state, double h, StepProblem& p) {
  const int B = model.num_bodies();
  p.weight.resize(B);
  p.target.resize(3, B);
  for (int i = 0; i < B; ++i) {
    const Vec3 coast = state.x.col(i) + h * state.v.col(i);
    if (state.inv_mass[i] == 0.0) {
      p.weight[i] = 0.0;
      p.target.col(i) = coast;
      continue;
    }
    const double m = model.mass[i];
    const double c = i < model.num_particles ? model.air_drag : 0.0;
    const double a = m / (h * h) + c / h;
    Vec3 b = (m / (h * h)) * coast + (c / h) * state.x.col(i);
    if (model.gravity_on[i]) b += m * model.gravity;
    p.weight[i] = a;
    p.target.col(i) = b / a;
  }
}

void build_spring_terms(const Model& model, const State& state, double h, StepProblem& p) {
  const Springs& s = model.springs;
  const std::size_t S = s.size();
  p.start_length.resize(S);
  p.stiffness.resize(S);
  p.rest.resize(S);
  for (std::size_t k = 0; k < S; ++k) {
    const double ln = (state.x.col(s.a[k]) - state.x.col(s.b[k])).norm();
    const double damper = s.kd[k] / h;
    const double total = s.ks[k] + damper;
    p.start_length[k] = ln;
    p.stiffness[k] = total;
    p.rest[k] = total > 0.0 ? (s.ks[k] * s.rest[k] + damper * ln) / total : s.rest[k];
  }
}

}  // namespace

Penetration deepest_penetration(const Colliders& c, const Vec3& y) {
  Penetration best;
  best.depth = -std::numeric_limits<double>::infinity();
  if (c.ground)
    best = Penetration{Vec3::UnitY(), c.ground_reach - y.y(), c.ground_friction, Vec3::Zero(), c.ground_restitution};
  for (std::size_t k = 0; k < c.centre.size(); ++k) {
    const Vec3 d = y - c.centre[k];
    const double r = d.norm();
    if (c.reach[k] - r <= best.depth) continue;
    best = Penetration{r > 0.0 ? Vec3(d / r) : Vec3(Vec3::UnitY()), c.reach[k] - r, c.friction[k], c.velocity[k],
                       c.restitution[k]};
  }
  return best;
}

void held_plane(const Colliders& c, const Vec3& from, const Vec3& y, Vec3& normal, double& plane) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < c.centre.size(); ++k) {
    const double gap = (y - c.centre[k]).norm() - c.reach[k];
    if (gap >= best) continue;
    sphere_held_plane(c.centre[k], c.reach[k], from, normal, plane);
    best = gap;
  }
  if (c.ground && y.y() - c.ground_reach < best) normal = Vec3::UnitY(), plane = c.ground_reach + kHeldClearance;
}

void build_step_problem(const Model& model, const State& state, double h, StepProblem& p) {
  p.h = h;
  p.start = state.x;
  build_body_terms(model, state, h, p);
  build_spring_terms(model, state, h, p);
  build_colliders(model, state, h, p.colliders);
}

double step_objective(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y) {
  double g = 0.0;
  for (int i = 0; i < model.num_bodies(); ++i)
    g += 0.5 * p.weight[i] * (y.col(i) - p.target.col(i)).squaredNorm();
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double l = (y.col(s.a[k]) - y.col(s.b[k])).norm();
    const double stretch = l - s.rest[k], rate = l - p.start_length[k];
    g += 0.5 * s.ks[k] * stretch * stretch + 0.5 * (s.kd[k] / p.h) * rate * rate;
  }
  return g;
}

double step_gradient(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y,
                     Eigen::Matrix3Xd& gradient) {
  const int B = model.num_bodies();
  gradient.resize(3, B);
  for (int i = 0; i < B; ++i) gradient.col(i) = p.weight[i] * (y.col(i) - p.target.col(i));
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3 d = y.col(s.a[k]) - y.col(s.b[k]);
    const double l = d.norm();
    if (l <= 0.0) continue;
    const Vec3 f = (p.stiffness[k] * (l - p.rest[k]) / l) * d;
    gradient.col(s.a[k]) += f;
    gradient.col(s.b[k]) -= f;
  }
  for (int i = 0; i < B; ++i)
    if (p.weight[i] == 0.0) gradient.col(i).setZero();
  return p.h * gradient.norm();
}

namespace {

// The contact a particle at y is in, if any: the nearest collider, within kContactBand of its reach.
bool in_contact(const Colliders& c, const Vec3& y, Penetration& contact) {
  if (!c.ground && c.centre.empty()) return false;
  contact = deepest_penetration(c, y);
  return contact.depth >= -kContactBand;
}

}  // namespace

// Takes out of r_i the reaction of a contact along n: its push into the collider.
void take_out_reaction(Eigen::Ref<Eigen::Vector3d> r, const Vec3& n) {
  const double push = n.dot(r);
  if (push > 0.0) r -= push * n;
}

double step_residual(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y,
                     const std::vector<HeldContact>* held, Eigen::Matrix3Xd& gradient) {
  step_gradient(model, p, y, gradient);
  if (held) {
    for (const HeldContact& c : *held) take_out_reaction(gradient.col(c.body), c.normal);
    return p.h * gradient.norm();
  }
  Penetration contact;
  for (int i = 0; i < model.num_particles; ++i)
    if (p.weight[i] > 0.0 && in_contact(p.colliders, y.col(i), contact)) take_out_reaction(gradient.col(i), contact.normal);
  return p.h * gradient.norm();
}

void respond_to_held_contacts(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y,
                              const std::vector<HeldContact>& held, Eigen::Matrix3Xd& gradient, State& state) {
  if (held.empty()) return;
  if (std::any_of(held.begin(), held.end(), [](const HeldContact& c) { return c.force < 0.0; }))
    step_gradient(model, p, y, gradient);
  for (const HeldContact& c : held) {
    const int i = c.body;
    const Penetration collider = deepest_penetration(p.colliders, y.col(i));  // its coefficients and velocity
    const double push = p.h * (c.force >= 0.0 ? c.force : std::max(0.0, c.normal.dot(gradient.col(i))));
    state.v.col(i) += held_contact_response(state.v.col(i) - collider.collider_velocity, c.normal, state.inv_mass[i],
                                            collider.restitution, collider.friction, push);
  }
}

void finish_step(const StepProblem& p, const Eigen::Matrix3Xd& y, State& state) {
  for (Eigen::Index i = 0; i < y.cols(); ++i) {
    if (p.weight[i] == 0.0) {  // immovable: keeps its velocity exactly, as every integrator
      state.x.col(i) += p.h * state.v.col(i);
      continue;
    }
    state.v.col(i) = (y.col(i) - p.start.col(i)) / p.h;
    state.x.col(i) = y.col(i);
  }
}

}  // namespace clothsim
