// Model: everything about a scene that does not change while it runs, as flat arrays.
// Built once from a SceneDef by build_model() (scene/build_model.h); never written afterwards (MuJoCo's mjModel).
//
// Bodies. The integrators act on one flat state of B = P + S bodies: the P cloth particles
// first, then the S spheres. A sphere is a body like a particle, with a radius; a kinematic
// sphere has inverse mass 0 and no gravity, so every integrator carries it along at its
// scripted (piecewise-constant) velocity exactly, and the collision response, written in
// inverse masses, never pushes it. Pinned particles have inverse mass 0 as well, in State,
// because events can pin and unpin them.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/method_settings.h"
#include "core/base/model_params.h"
#include "core/springs/spring_layout.h"
#include "core/springs/springs.h"

namespace clothsim {

// A change scheduled at a time: pin/unpin a particle or set a kinematic sphere's velocity.
struct TimedAction {
  enum class Kind : std::uint8_t { Pin, Unpin, SetVelocity } kind;
  double t;        // s
  int body;        // body index (particle or P + sphere)
  Vec3 velocity;   // SetVelocity only
};

struct Model {
  std::string name;
  std::string source;  // scene file path

  // Bodies (B = P + S).
  int num_particles = 0;              // P
  int num_spheres = 0;                // S
  int grid_nx = 0, grid_ny = 0;       // particle p = j * grid_nx + i
  Eigen::VectorXd mass;               // (B) kg; kinematic spheres: +inf
  Eigen::VectorXd initial_inv_mass;   // (B) 1/kg; 0 for pinned particles and kinematic spheres
  std::vector<std::uint8_t> gravity_on;  // (B) 1 if gravity acts on the body
  Eigen::Matrix3Xd initial_x, initial_v;  // (3 x B)

  Springs springs;
  SpringLayout spring_layout;  // the same springs in grid-stencil families, for the SIMD pass

  // Spheres (S), indexed s; body index P + s.
  std::vector<double> sphere_radius;        // (S) m
  std::vector<double> sphere_restitution;   // (S) cloth-sphere C_R
  std::vector<double> sphere_friction;      // (S)
  std::vector<std::uint8_t> sphere_kinematic;  // (S)

  bool has_ground = false;
  GroundDef ground;
  CollisionDef collision;

  Vec3 gravity{0.0, -9.8, 0.0};  // m/s^2
  double air_drag = 0.0;         // N s/m, acts on cloth particles

  std::vector<TimedAction> timeline;  // sorted by t (stable in scene order)
  std::vector<std::uint32_t> triangles;  // (3 x T) cloth triangles for rendering, CCW seen from +normal

  double duration = 0.0, dt = 0.0;
  IntegratorKind integrator = kDefaultIntegrator;
  // The scene's method settings (its implicit:, xpbd:, ... blocks), the defaults every Run of
  // this model starts from; a lane overrides its own run's copy (method_settings.h). No step
  // reads these: steps read the run's (StepContext::settings).
  ImplicitDef implicit;
  SolverDefs solvers;  // xpbd, projective_dynamics, vbd options
  AdaptiveDef adaptive;  // bs3, dopri5, rkf78: the error control's tolerances
  MethodDefs methods;  // newmark's and generalized_alpha's parameters
  DivergenceDef divergence;
  double energy_scale = 1.0;  // J, what kinetic energy is compared with to call a run diverged

  MethodSettings method_defaults() const { return {implicit, solvers, adaptive, methods}; }
  int num_bodies() const { return num_particles + num_spheres; }
  SpringPath spring_path() const { return clothsim::spring_path(spring_layout, springs.size(), num_particles); }
  int sphere_body(int s) const { return num_particles + s; }
};

}  // namespace clothsim
