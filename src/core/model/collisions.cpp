#include "collisions.h"

#include <algorithm>
#include <cmath>

#include "core/model/barrier_contacts.h"

namespace clothsim {

double contact_impulse(double u_a, double u_b, double w_a, double w_b, double restitution) {
  const double w = w_a + w_b;
  const double approach = u_a - u_b;  // normal points from b to a: negative means closing
  if (w == 0.0 || approach >= 0.0) return 0.0;
  return -(1.0 + restitution) * approach / w;
}

Vec3 friction_impulse(const Vec3& vt, double jn, double w_a, double w_b, double mu) {
  const double w = w_a + w_b;
  const double speed = vt.norm();
  if (mu <= 0.0 || w == 0.0 || speed == 0.0) return Vec3::Zero();
  // The impulse that would stop the sliding, capped by the Coulomb cone |j_t| <= mu |j_n|.
  const double stop = speed / w;
  return -std::min(stop, mu * std::abs(jn)) * (vt / speed);
}

Vec3 held_contact_response(const Vec3& rel, const Vec3& n, double w, double restitution, double friction,
                           double held) {
  const double u = rel.dot(n);
  const double correction = std::max(0.0, u);
  const double jn = contact_impulse(u - correction, 0.0, w, 0.0, restitution);
  const Vec3 J = jn * n + friction_impulse(rel - u * n, jn + held, w, 0.0, friction);
  return w * J - correction * n;
}

namespace {

// One contact between body a and body b (b may be immovable) along unit normal n (b -> a).
// Applies the restitution impulse and friction; nothing when they are separating.
void exchange_impulse(State& s, int a, int b_or_minus1, const Vec3& n, double restitution,
                      double friction) {
  const double w_a = s.inv_mass[a];
  const double w_b = b_or_minus1 >= 0 ? s.inv_mass[b_or_minus1] : 0.0;
  const Vec3 vb = b_or_minus1 >= 0 ? Vec3(s.v.col(b_or_minus1)) : Vec3::Zero();
  const Vec3 rel = s.v.col(a) - vb;
  const double u_rel = rel.dot(n);
  const double jn = contact_impulse(u_rel, 0.0, w_a, w_b, restitution);
  if (jn == 0.0) return;
  const Vec3 vt = rel - u_rel * n;
  const Vec3 J = jn * n + friction_impulse(vt, jn, w_a, w_b, friction);
  s.v.col(a) += w_a * J;
  if (b_or_minus1 >= 0) s.v.col(b_or_minus1) -= w_b * J;
}

// Pushes a out of b to distance `target` along n, moving only movable bodies: the
// particle if it can move (the seed projects the particle), otherwise b.
void separate(State& s, int a, int b, const Vec3& n, double depth) {
  if (s.inv_mass[a] > 0.0) s.x.col(a) += depth * n;
  else if (b >= 0 && s.inv_mass[b] > 0.0) s.x.col(b) -= depth * n;
}

}  // namespace

ContactCounts count_barrier_contacts(const Model& model, const State& state) {
  ContactCounts counts;
  const double dhat = model.collision.barrier_distance;
  for_each_barrier_pair(model, state.inv_mass, [&](const BarrierPair& pair) {
    if (!pair_within_reach(model, pair, state.x, dhat)) return;
    const bool particle = pair.a < model.num_particles;
    int& n = pair.b < 0 ? (particle ? counts.cloth_ground : counts.sphere_ground)
                        : (particle ? counts.cloth_sphere : counts.sphere_sphere);
    ++n;
  });
  return counts;
}

ContactCounts resolve_collisions(const Model& model, State& state) {
  // The one place the contact model is switched: the barrier acted inside the step already.
  if (uses_barrier(model)) return count_barrier_contacts(model, state);
  ContactCounts counts;
  const int P = model.num_particles;
  const double margin = model.collision.margin;

  // Cloth vs spheres: |x - c| < r + margin.
  for (int s = 0; s < model.num_spheres; ++s) {
    const int b = model.sphere_body(s);
    const double reach = model.sphere_radius[s] + margin;
    const double reach2 = reach * reach;
    for (int p = 0; p < P; ++p) {
      const Vec3 d = state.x.col(p) - state.x.col(b);
      const double dist2 = d.squaredNorm();
      if (dist2 >= reach2) continue;
      const double dist = std::sqrt(dist2);
      // A particle exactly at the centre has no normal: push it straight up.
      const Vec3 n = dist > 1e-12 ? Vec3(d / dist) : Vec3::UnitY();
      exchange_impulse(state, p, b, n, model.sphere_restitution[s], model.sphere_friction[s]);
      separate(state, p, b, n, reach - dist);
      ++counts.cloth_sphere;
      if (state.inv_mass[b] == 0.0 && state.inv_mass[p] > 0.0) ++counts.projected;
    }
  }

  // Spheres vs spheres (optional), with their own restitution.
  if (model.collision.sphere_sphere) {
    for (int s = 0; s < model.num_spheres; ++s)
      for (int q = s + 1; q < model.num_spheres; ++q) {
        const int a = model.sphere_body(s), b = model.sphere_body(q);
        const Vec3 d = state.x.col(a) - state.x.col(b);
        const double reach = model.sphere_radius[s] + model.sphere_radius[q];
        const double dist = d.norm();
        if (dist >= reach) continue;
        const Vec3 n = dist > 1e-12 ? Vec3(d / dist) : Vec3::UnitY();
        exchange_impulse(state, a, b, n, model.collision.sphere_restitution, 0.0);
        // Split the overlap by inverse mass so neither sphere is favoured.
        const double wa = state.inv_mass[a], wb = state.inv_mass[b];
        if (wa + wb > 0.0) {
          const double depth = reach - dist;
          state.x.col(a) += depth * wa / (wa + wb) * n;
          state.x.col(b) -= depth * wb / (wa + wb) * n;
        }
        ++counts.sphere_sphere;
      }
  }

  // Ground plane y = h: particles within margin, spheres touching it.
  if (model.has_ground) {
    const double h = model.ground.height;
    const Vec3 n = Vec3::UnitY();
    for (int p = 0; p < P; ++p) {
      const double gap = state.x(1, p) - (h + margin);
      if (gap >= 0.0) continue;
      exchange_impulse(state, p, -1, n, model.ground.restitution, model.ground.friction);
      if (state.inv_mass[p] > 0.0) {
        state.x(1, p) -= gap;
        ++counts.projected;
      }
      ++counts.cloth_ground;
    }
    for (int s = 0; s < model.num_spheres; ++s) {
      const int b = model.sphere_body(s);
      const double gap = state.x(1, b) - model.sphere_radius[s] - h;
      if (gap >= 0.0 || state.inv_mass[b] == 0.0) continue;
      exchange_impulse(state, b, -1, n, model.ground.restitution, model.ground.friction);
      state.x(1, b) -= gap;
      ++counts.sphere_ground;
    }
  }
  return counts;
}

}  // namespace clothsim
