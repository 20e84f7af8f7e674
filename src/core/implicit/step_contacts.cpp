#include "step_contacts.h"

#include <cmath>
#include <limits>

#include "contact_kernels.h"
#include "core/model/collisions.h"

namespace clothsim {
namespace {

// A particle's candidate contact: the collider, the normal and the plane of the held position.
struct Candidate {
  std::int32_t collider = -2;  // -2: none
  Vec3 normal = Vec3::UnitY();
  double plane = 0.0;
  double gap = std::numeric_limits<double>::infinity();  // signed distance of `at` beyond reach
};

bool is_kinematic_sphere(const Model& model, const State& state, int s) {
  return state.inv_mass[model.sphere_body(s)] == 0.0;
}

// The nearest immovable collider to the end position `at` of particle p (starting at `from`):
// the normal points from the sphere's end-of-step centre to where the particle starts, so a
// particle that would pass into the sphere is held on the side it came from.
Candidate nearest_collider(const Model& model, const State& start, double h, const Vec3& from,
                           const Vec3& at) {
  Candidate best;
  const double margin = model.collision.margin;
  for (int s = 0; s < model.num_spheres; ++s) {
    if (!is_kinematic_sphere(model, start, s)) continue;
    const int b = model.sphere_body(s);
    const Vec3 centre = start.x.col(b) + h * start.v.col(b);
    const double reach = model.sphere_radius[s] + margin;
    const double gap = (at - centre).norm() - reach;
    if (gap >= best.gap) continue;
    best.collider = s;
    sphere_held_plane(centre, reach, from, best.normal, best.plane);
    best.gap = gap;
  }
  if (model.has_ground) {
    const double surface = model.ground.height + margin;
    const double gap = at.y() - surface;
    if (gap < best.gap) {
      best.collider = -1;
      best.normal = Vec3::UnitY();
      best.plane = surface + kContactClearance;
      best.gap = gap;
    }
  }
  return best;
}

// Where a particle could be within `slack` beyond an immovable collider's reach: the ground's
// height and each kinematic sphere's end-of-step centre and reach, gathered once per pass so
// that the particles far from every collider (most of a sheet) cost a few comparisons each
// and no square root, instead of nearest_collider's full search. The test is conservative
// (its bounds are widened by far more than the rounding of the squares), and nearest_collider
// still decides for every particle that passes it, so the contacts found are the same.
class NearColliders {
 public:
  NearColliders(const Model& model, const State& start, double h, double slack) {
    const double margin = model.collision.margin;
    for (int s = 0; s < model.num_spheres; ++s) {
      if (!is_kinematic_sphere(model, start, s)) continue;
      const int b = model.sphere_body(s);
      const double bound = model.sphere_radius[s] + margin + slack;
      centre_.push_back(start.x.col(b) + h * start.v.col(b));
      bound2_.push_back(bound * bound * (1.0 + 1e-9) + 1e-18);
    }
    ground_ = model.has_ground ? model.ground.height + margin + slack + 1e-9
                               : -std::numeric_limits<double>::infinity();
  }
  bool maybe(const Vec3& at) const {
    if (at.y() < ground_) return true;
    for (std::size_t s = 0; s < centre_.size(); ++s)
      if ((at - centre_[s]).squaredNorm() < bound2_[s]) return true;
    return false;
  }
  // maybe() for n particles' end positions at once (contact_kernels.h: x, or x + h v, or
  // x + h (v + g)): the particles that pass, in order. The same test in SIMD, whose rounding
  // of the squares the widened bounds cover as they cover maybe()'s.
  void screen(const double* x, const double* v, const double* g, double h, std::size_t n,
              std::vector<std::int32_t>& near) const {
    NearScreen s;
    s.centre = centre_.empty() ? nullptr : centre_.data()->data();
    s.bound2 = bound2_.data();
    s.spheres = centre_.size();
    s.ground = ground_;
    near_screen(s, x, v, g, h, n, near);
  }

 private:
  std::vector<Vec3> centre_;
  std::vector<double> bound2_;
  double ground_;
};

void hold(StepContacts& contacts, int p, const Candidate& c) {
  contacts.filter.body.push_back(p);
  contacts.filter.normal.push_back(c.normal);
  contacts.plane.push_back(c.plane);
  contacts.collider.push_back(c.collider);
  contacts.held[p] = 1;
}

}  // namespace

void predict_step_contacts(const Model& model, const State& start, double h,
                           const Eigen::Matrix3Xd* guess, StepContacts& contacts) {
  contacts.filter.clear();
  contacts.plane.clear();
  contacts.collider.clear();
  contacts.held.assign(model.num_particles, 0);
  contacts.let_go.assign(model.num_particles, 0);
  if (model.collision.model == ContactModel::Barrier) return;  // contacts are Phi's barrier terms
  // Held last step: likely resting on the collider, so held again unless it is leaving.
  std::vector<std::uint8_t>& was_held = contacts.held_before;
  was_held.assign(model.num_particles, 0);
  for (const std::int32_t p : start.implicit.held)
    if (p < model.num_particles) was_held[p] = 1;
  const double margin = model.collision.margin;
  const NearColliders near(model, start, h, margin);
  near.screen(start.x.data(), start.v.data(), guess ? guess->data() : nullptr, h,
              static_cast<std::size_t>(model.num_particles), contacts.near);
  for (const int p : contacts.near) {
    if (start.inv_mass[p] == 0.0) continue;
    Vec3 v = start.v.col(p);
    if (guess) v += guess->col(p);
    const Vec3 at = start.x.col(p) + h * v;
    if (!near.maybe(at)) continue;
    const Candidate c = nearest_collider(model, start, h, start.x.col(p), at);
    if (c.gap < (was_held[p] ? margin : 0.0)) hold(contacts, p, c);
  }
}

void place_on_planes(const StepContacts& contacts, const State& start, double h,
                     Eigen::Matrix3Xd& dv) {
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const int p = contacts.filter.body[c];
    const Vec3& n = contacts.filter.normal[c];
    const Vec3 y = start.x.col(p) + h * (start.v.col(p) + dv.col(p));
    dv.col(p) += ((contacts.plane[c] - n.dot(y)) / h) * n;
  }
}

bool take_in_step_contacts(const Model& model, const State& start, double h,
                           const Eigen::Matrix3Xd& y, StepContacts& contacts) {
  if (model.collision.model == ContactModel::Barrier) return false;  // none held: the barrier acts
  bool changed = false;
  const NearColliders near(model, start, h, 0.0);
  near.screen(y.data(), nullptr, nullptr, h, static_cast<std::size_t>(model.num_particles), contacts.near);
  for (const int p : contacts.near) {
    if (start.inv_mass[p] == 0.0 || contacts.held[p] || !near.maybe(y.col(p))) continue;
    const Candidate c = nearest_collider(model, start, h, start.x.col(p), y.col(p));
    if (c.gap < 0.0) {
      hold(contacts, p, c);
      changed = true;
    }
  }
  return changed;
}

// A held particle that pulls does positive work on the cloth as the step ends (the constraint
// drags it towards the collider), so it is let go each time it pulls, up to kMaxLetGo times a
// step: once was not enough, as one taken in again could end the step pulling (docs/integrators.md).
constexpr std::uint8_t kMaxLetGo = 3;

bool let_go_step_contacts(const Eigen::Matrix3Xd& gradient, StepContacts& contacts) {
  bool changed = false;
  // Let go of the pulling ones, keeping the order of the rest.
  std::size_t kept = 0;
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const int p = contacts.filter.body[c];
    if (contacts.let_go[p] < kMaxLetGo && contacts.filter.normal[c].dot(gradient.col(p)) < 0.0) {
      contacts.held[p] = 0;
      ++contacts.let_go[p];
      changed = true;
      continue;
    }
    contacts.filter.body[kept] = p;
    contacts.filter.normal[kept] = contacts.filter.normal[c];
    contacts.plane[kept] = contacts.plane[c];
    contacts.collider[kept] = contacts.collider[c];
    ++kept;
  }
  contacts.filter.body.resize(kept);
  contacts.filter.normal.resize(kept);
  contacts.plane.resize(kept);
  contacts.collider.resize(kept);
  return changed;
}

bool update_step_contacts(const Model& model, const State& start, double h,
                          const Eigen::Matrix3Xd& y, const Eigen::Matrix3Xd& gradient,
                          StepContacts& contacts) {
  const bool let_go = let_go_step_contacts(gradient, contacts);
  return take_in_step_contacts(model, start, h, y, contacts) || let_go;
}

void respond_to_step_contacts(const Model& model, const StepContacts& contacts,
                              const Eigen::Matrix3Xd& gradient, State& state) {
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const int p = contacts.filter.body[c];
    const Vec3& n = contacts.filter.normal[c];
    const int s = contacts.collider[c];
    const Vec3 collider_v = s >= 0 ? Vec3(state.v.col(model.sphere_body(s))) : Vec3::Zero();
    const double restitution = s >= 0 ? model.sphere_restitution[s] : model.ground.restitution;
    const double friction = s >= 0 ? model.sphere_friction[s] : model.ground.friction;
    // A held particle is in contact at the end of the step, so it has no separating normal
    // velocity of its own: what it has comes from being moved out of a penetration it started
    // in (the position correction, which the post-step projection does not turn into velocity
    // either), and is removed before the restitution response acts on the approach speed.
    const double held_impulse = std::max(0.0, n.dot(gradient.col(p)));
    state.v.col(p) += held_contact_response(state.v.col(p) - collider_v, n, state.inv_mass[p], restitution,
                                            friction, held_impulse);
  }
}

}  // namespace clothsim
