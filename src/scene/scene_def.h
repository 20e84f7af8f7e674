// SceneDef: a validated scene as plain values, exactly what the YAML said with the
// defaults filled in. Defaults live here (member initialisers) and nowhere else; the
// parser (scene_parser.cpp) only overwrites what a file sets, and docs/scenes.md lists them.
// Units are SI throughout: m, s, kg, N/m, N s/m.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/base/model_params.h"
#include "core/base/method_params.h"
#include "view/render_settings.h"

namespace clothsim {

struct SpringParams {
  double stiffness = 20000.0;  // N/m
  double damping = 750.0;      // N s/m, along the spring axis only
};

enum class ClothPlane { XZ, XY };  // xz: lying flat (normal +y); xy: hanging (normal +z)

// Some particles of the grid, as cloth.pinned and an event's pin/unpin name them
// (docs/scenes.md): a named set, or an inclusive range of columns and rows ([i, j] is the
// 1 x 1 range). Edges are in grid terms: row j = 0 is the top edge (the top of a hanging
// xy cloth), column i = 0 the left edge. Resolved to particles by selected_particles()
// (model.h), so a scene's pins follow its grid when --set changes cloth.particles.
struct GridSelection {
  enum class Kind { Corners, TopEdge, BottomEdge, LeftEdge, RightEdge, Range };
  Kind kind = Kind::Range;
  int i0 = 0, i1 = 0;  // Range: columns i0..i1, 0 <= i0 <= i1 < nx
  int j0 = 0, j1 = 0;  // Range: rows j0..j1, 0 <= j0 <= j1 < ny
};

struct ClothDef {
  int nx = 25, ny = 25;           // particles along each axis; [2, 1] is a single spring
  double size_x = 4.0, size_y = 4.0;  // m, extent along each axis (ignored along an axis with 1 particle)
  Vec3 center{0.0, 1.0, 0.0};      // m
  ClothPlane plane = ClothPlane::XZ;
  double particle_mass = 1.0;      // kg per particle
  std::optional<SpringParams> structural, shear, bend;  // absent: not built at all
  // Pinned at t = 0: the union of these selections; empty (pinned: none) pins nothing.
  std::vector<GridSelection> pinned{{GridSelection::Kind::Corners}};
  // Initial displacement of particle (nx-1, 0) along the first axis, m; lets spring.yaml
  // start stretched. Also an initial velocity for every free particle.
  double initial_stretch = 0.0;
  Vec3 initial_velocity{0.0, 0.0, 0.0};  // m/s
};

struct Keyframe {
  double t = 0.0;   // s: from this time on the sphere moves with `velocity`
  Vec3 velocity{0.0, 0.0, 0.0};  // m/s
};

struct SphereDef {
  Vec3 center{0.0, 0.0, 0.0};     // m
  double radius = 1.0;             // m
  bool kinematic = true;           // true: infinite mass, moves only as scripted
  double mass = 1.0;               // kg, dynamic spheres only
  bool gravity = true;             // dynamic spheres: whether gravity acts on it
  double restitution = 0.0;        // cloth-sphere coefficient of restitution C_R, [0, 1]
  double friction = 0.0;           // Coulomb coefficient for cloth-sphere contact, >= 0
  Vec3 velocity{0.0, 0.0, 0.0};    // m/s initial
  std::vector<Keyframe> motion;    // kinematic spheres: velocity keyframes, increasing t
};

struct EventDef {
  double t = 0.0;                      // s
  std::vector<GridSelection> pin, unpin;  // particles to pin (freeze) or release at t
};

struct SceneDef {
  std::string source;              // path the scene came from, for messages
  std::string name = "scene";
  double duration = 5.0;           // s simulated
  double dt = 1e-4;                // s per step
  IntegratorKind integrator = kDefaultIntegrator;
  Vec3 gravity{0.0, -9.8, 0.0};    // m/s^2
  double air_drag = 0.0;           // N s/m per particle, viscous: f = -c v
  ClothDef cloth;
  std::vector<SphereDef> spheres;
  std::optional<GroundDef> ground;
  CollisionDef collision;
  std::vector<EventDef> events;
  RenderDef render;
  ImplicitDef implicit;
  SolverDefs solvers;
  AdaptiveDef adaptive;  // bs3, dopri5, rkf78: the error control's tolerances (a lane's :tol=)
  MethodDefs methods;    // newmark's and generalized_alpha's parameters (a lane's :beta=, :gamma=, :rho=)  // xpbd, projective_dynamics, vbd blocks
  DivergenceDef divergence;
};

}  // namespace clothsim
