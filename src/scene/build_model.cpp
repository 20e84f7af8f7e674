// SceneDef -> Model: the particle grid, its springs (only the types the scene declares),
// the spheres as bodies, and the timeline of scripted actions.
#include "scene/build_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/model/barrier_contacts.h"
#include "core/springs/spring_force.h"
#include "scene/memory_estimate.h"

namespace clothsim {
namespace {

// Grid position of particle (i, j). xz lies flat at the centre's height; xy hangs with
// row j = 0 at the top. Along an axis with one particle the cloth has no extent.
Vec3 grid_position(const ClothDef& c, int i, int j) {
  const double u = c.nx > 1 ? static_cast<double>(i) / (c.nx - 1) - 0.5 : 0.0;
  const double w = c.ny > 1 ? static_cast<double>(j) / (c.ny - 1) - 0.5 : 0.0;
  if (c.plane == ClothPlane::XZ) return c.center + Vec3(u * c.size_x, 0.0, w * c.size_y);
  return c.center + Vec3(u * c.size_x, -w * c.size_y, 0.0);
}

void add_spring(Springs& s, const Eigen::Matrix3Xd& x, int a, int b, const SpringParams& p,
                SpringType type) {
  s.a.push_back(std::min(a, b));
  s.b.push_back(std::max(a, b));
  s.rest.push_back((x.col(a) - x.col(b)).norm());  // rest length = initial distance (the seed's)
  s.ks.push_back(p.stiffness);
  s.kd.push_back(p.damping);
  s.type.push_back(type);
}

// The seed's connectivity: structural to the 4-neighbours, shear across each cell's two
// diagonals, bend to the neighbour two away along each axis.
Springs build_springs(const ClothDef& c, const Eigen::Matrix3Xd& x) {
  Springs s;
  // Reserved whole: growing by push_back would hold the old and the new buffer at once, 1.5x
  // the arrays' final size at the peak, past what model_bytes() promises.
  const auto count = static_cast<std::size_t>(spring_count(c));
  s.a.reserve(count), s.b.reserve(count), s.rest.reserve(count), s.ks.reserve(count), s.kd.reserve(count);
  s.type.reserve(count);
  const auto id = [&](int i, int j) { return j * c.nx + i; };
  if (c.structural) {
    for (int j = 0; j < c.ny; ++j)
      for (int i = 0; i + 1 < c.nx; ++i) add_spring(s, x, id(i, j), id(i + 1, j), *c.structural, SpringType::Structural);
    for (int j = 0; j + 1 < c.ny; ++j)
      for (int i = 0; i < c.nx; ++i) add_spring(s, x, id(i, j), id(i, j + 1), *c.structural, SpringType::Structural);
  }
  if (c.shear) {
    for (int j = 0; j + 1 < c.ny; ++j)
      for (int i = 0; i + 1 < c.nx; ++i) {
        add_spring(s, x, id(i, j), id(i + 1, j + 1), *c.shear, SpringType::Shear);
        add_spring(s, x, id(i + 1, j), id(i, j + 1), *c.shear, SpringType::Shear);
      }
  }
  if (c.bend) {
    for (int j = 0; j < c.ny; ++j)
      for (int i = 0; i + 2 < c.nx; ++i) add_spring(s, x, id(i, j), id(i + 2, j), *c.bend, SpringType::Bend);
    for (int j = 0; j + 2 < c.ny; ++j)
      for (int i = 0; i < c.nx; ++i) add_spring(s, x, id(i, j), id(i, j + 2), *c.bend, SpringType::Bend);
  }
  return s;
}

// Two triangles per grid cell, wound so the front faces +y (xz) or +z (xy).
std::vector<std::uint32_t> build_triangles(const ClothDef& c) {
  std::vector<std::uint32_t> t;
  if (c.nx > 1 && c.ny > 1) t.reserve(6 * static_cast<std::size_t>(c.nx - 1) * static_cast<std::size_t>(c.ny - 1));
  for (int j = 0; j + 1 < c.ny; ++j)
    for (int i = 0; i + 1 < c.nx; ++i) {
      const std::uint32_t p00 = j * c.nx + i, p10 = p00 + 1, p01 = p00 + c.nx, p11 = p01 + 1;
      t.insert(t.end(), {p00, p11, p10, p00, p01, p11});
    }
  return t;
}

}  // namespace

std::vector<int> selected_particles(const std::vector<GridSelection>& selection, int nx, int ny) {
  using K = GridSelection::Kind;
  std::vector<int> out;
  const auto add = [&](int i0, int i1, int j0, int j1) {
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) out.push_back(j * nx + i);
  };
  for (const GridSelection& g : selection) {
    switch (g.kind) {
      case K::Corners:
        for (int j : {0, ny - 1})
          for (int i : {0, nx - 1}) add(i, i, j, j);
        break;
      case K::TopEdge: add(0, nx - 1, 0, 0); break;
      case K::BottomEdge: add(0, nx - 1, ny - 1, ny - 1); break;
      case K::LeftEdge: add(0, 0, 0, ny - 1); break;
      case K::RightEdge: add(nx - 1, nx - 1, 0, ny - 1); break;
      case K::Range: add(g.i0, g.i1, g.j0, g.j1); break;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

namespace {

// The cloth's particles: grid positions, masses, springs, pins and the initial velocity.
void add_cloth(Model& m, const ClothDef& c) {
  const int P = m.num_particles;
  for (int j = 0; j < c.ny; ++j)
    for (int i = 0; i < c.nx; ++i) m.initial_x.col(j * c.nx + i) = grid_position(c, i, j);
  m.springs = build_springs(c, m.initial_x);  // rest lengths from the unstretched grid
  m.spring_layout = build_spring_layout(m.springs, c.nx, c.ny);
  if (c.initial_stretch != 0.0) {
    const Vec3 axis = Vec3::UnitX();  // the first axis of both planes
    m.initial_x.col(c.nx - 1) += c.initial_stretch * axis;
  }
  for (int p = 0; p < P; ++p) {
    m.mass[p] = c.particle_mass;
    m.initial_inv_mass[p] = 1.0 / c.particle_mass;
    m.gravity_on[p] = 1;
    m.initial_v.col(p) = c.initial_velocity;
  }
  for (const int p : selected_particles(c.pinned, c.nx, c.ny)) {
    m.initial_inv_mass[p] = 0.0;
    m.initial_v.col(p).setZero();
  }
  m.triangles = build_triangles(c);
}

// The spheres as bodies after the particles; a kinematic sphere's keyframes join the timeline.
void add_spheres(Model& m, const std::vector<SphereDef>& spheres) {
  for (int s = 0; s < m.num_spheres; ++s) {
    const SphereDef& d = spheres[s];
    const int b = m.sphere_body(s);
    m.initial_x.col(b) = d.center;
    m.initial_v.col(b) = d.velocity;
    if (d.kinematic) {
      m.mass[b] = std::numeric_limits<double>::infinity();
      m.initial_inv_mass[b] = 0.0;
    } else {
      m.mass[b] = d.mass;
      m.initial_inv_mass[b] = 1.0 / d.mass;
      m.gravity_on[b] = d.gravity ? 1 : 0;
    }
    m.sphere_radius.push_back(d.radius);
    m.sphere_restitution.push_back(d.restitution);
    m.sphere_friction.push_back(d.friction);
    m.sphere_kinematic.push_back(d.kinematic ? 1 : 0);
    for (const Keyframe& k : d.motion)
      m.timeline.push_back({TimedAction::Kind::SetVelocity, k.t, b, k.velocity});
  }
}

// Pin and unpin events, then the whole timeline in time order (stable: scene order on ties).
void add_events(Model& m, const std::vector<EventDef>& events, const ClothDef& c) {
  for (const EventDef& e : events) {
    for (const int p : selected_particles(e.pin, c.nx, c.ny))
      m.timeline.push_back({TimedAction::Kind::Pin, e.t, p, Vec3::Zero()});
    for (const int p : selected_particles(e.unpin, c.nx, c.ny))
      m.timeline.push_back({TimedAction::Kind::Unpin, e.t, p, Vec3::Zero()});
  }
  std::stable_sort(m.timeline.begin(), m.timeline.end(),
                   [](const TimedAction& a, const TimedAction& b) { return a.t < b.t; });
}

// Energy scale for the divergence bound: the potential energy the scene could release
// falling through its own size, plus what its springs and motion hold at the start.
double energy_scale(const Model& m, const ClothDef& c) {
  const double extent = 1.0 + std::hypot(c.size_x, c.size_y);
  double scale = 1.0;
  for (int b = 0; b < m.num_bodies(); ++b)
    if (std::isfinite(m.mass[b]))
      scale += m.mass[b] * (m.gravity.norm() * extent + 0.5 * m.initial_v.col(b).squaredNorm());
  for (std::size_t s = 0; s < m.springs.size(); ++s)
    scale += spring_energy(m.initial_x.col(m.springs.a[s]), m.initial_x.col(m.springs.b[s]),
                           m.springs.rest[s], m.springs.ks[s]);
  return scale;
}

}  // namespace

Model build_model(const SceneDef& scene) {
  Model m;
  m.name = scene.name;
  m.source = scene.source;
  const ClothDef& c = scene.cloth;
  m.grid_nx = c.nx;
  m.grid_ny = c.ny;
  m.num_particles = c.nx * c.ny;
  m.num_spheres = static_cast<int>(scene.spheres.size());
  const int B = m.num_bodies();
  m.mass.resize(B);
  m.initial_inv_mass.resize(B);
  m.gravity_on.assign(B, 0);
  m.initial_x.resize(3, B);
  m.initial_v.setZero(3, B);

  add_cloth(m, c);
  add_spheres(m, scene.spheres);
  add_events(m, scene.events, c);
  m.has_ground = scene.ground.has_value();
  if (m.has_ground) m.ground = *scene.ground;
  m.collision = scene.collision;
  if (m.collision.barrier_stiffness == 0.0 && m.num_particles > 0)  // chosen from the scene (barrier_kernels.h)
    m.collision.barrier_stiffness =
        default_barrier_stiffness(c.particle_mass, scene.gravity, m.collision.barrier_distance);
  m.gravity = scene.gravity;
  m.air_drag = scene.air_drag;
  m.duration = scene.duration;
  m.dt = scene.dt;
  m.integrator = scene.integrator;
  m.implicit = scene.implicit;
  m.solvers = scene.solvers;
  m.adaptive = scene.adaptive;
  m.methods = scene.methods;
  m.divergence = scene.divergence;
  m.energy_scale = energy_scale(m, c);
  return m;
}

}  // namespace clothsim
