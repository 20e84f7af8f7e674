// The barrier contact model over whole scenes: the default stays the course's projection,
// the new keys parse (and fail with their line), forces are minus the energy's gradient,
// a particle dropping onto a sphere is a smooth ODE that RK4 solves at order 4, symplectic
// Euler keeps the energy, a dynamic sphere conserves momentum with the cloth, and implicit
// Euler and VBD never let a distance reach zero.
#include "core/model/barrier_contacts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "test_support.h"
#include "core/model/diagnostics.h"
#include "core/model/forces.h"
#include "core/run/simulation.h"

namespace clothsim {
namespace {

using testing::model_from_yaml;

// One particle above a kinematic unit sphere, slightly off its axis, falling onto it from
// 0.1 m and bouncing off the barrier (d-hat 0.05 m, the stiffness chosen from the scene).
const char* kDrop = R"(
gravity: [0, -9.8, 0]
cloth: {particles: [1, 1], center: [0.05, 1.1, 0.02], pinned: none}
spheres: [{center: [0, 0, 0], radius: 1.0}]
collision: {model: barrier, barrier_distance: 0.05}
)";

TEST(BarrierModel, ProjectionStaysTheDefault) {
  const Model drape = build_model(load_scene(testing::scene_path("drape.yaml")));
  EXPECT_EQ(drape.collision.model, ContactModel::Projection);
  EXPECT_FALSE(uses_barrier(drape));
  EXPECT_EQ(compute_energies(drape, initial_state(drape)).contact, 0.0);
  const Model smooth = build_model(load_scene(testing::scene_path("drape_smooth.yaml")));
  EXPECT_TRUE(uses_barrier(smooth));
  EXPECT_GT(smooth.collision.barrier_stiffness, 0.0);  // chosen from the scene
}

TEST(BarrierModel, DefaultStiffnessHoldsAParticlesWeightAtHalfTheReach) {
  const Model m = model_from_yaml(kDrop);
  const BarrierParams p = barrier_params(m);
  EXPECT_NEAR(-barrier_derivative(0.025, p), 9.8, 1e-9);
  const Model set = model_from_yaml(kDrop, {"collision.barrier_stiffness=5000"});
  EXPECT_NEAR(barrier_second_derivative(0.025, barrier_params(set)), 5000.0, 1e-6);
}

TEST(BarrierModel, BadKeysNameTheirLine) {
  const auto message = [](const std::string& yaml) {
    try {
      model_from_yaml(yaml);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string cloth = "cloth: {particles: [2, 2]}\n";
  EXPECT_NE(message(cloth + "collision:\n  model: penalty\n").find("inline.yaml:3: collision.model: unknown contact model"),
            std::string::npos);
  EXPECT_NE(message(cloth + "collision:\n  model: barrier\n  barrier_distance: 0\n").find("inline.yaml:4: collision.barrier_distance"),
            std::string::npos);
  EXPECT_NE(message(cloth + "collision:\n  barrier_stiffness: -3\n").find("inline.yaml:3: collision.barrier_stiffness"),
            std::string::npos);
  EXPECT_NE(message(cloth + "collision:\n  friction_velocity: x\n").find("inline.yaml:3: collision.friction_velocity"),
            std::string::npos);
  const std::string refused = message("integrator: xpbd\n" + cloth + "collision:\n  model: barrier\n");
  EXPECT_NE(refused.find("inline.yaml:4: collision.model: xpbd has no barrier contact"), std::string::npos) << refused;
}

TEST(BarrierModel, XpbdAndProjectiveDynamicsRefuseABarrierSceneWithTheKey) {
  const Model m = model_from_yaml(kDrop);
  for (IntegratorKind kind : {IntegratorKind::Xpbd, IntegratorKind::ProjectiveDynamics}) {
    State s = initial_state(m);
    Workspace ws;
    try {
      integrate(kind, m, s, 1e-3, ws);
      ADD_FAILURE() << "ran";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("collision.model: ", 0), 0u) << e.what();
    }
  }
}

// Forces are minus the potential's gradient (central differences of barrier_potential), for
// the cloth's particles against a sphere and the ground.
TEST(BarrierModel, ForcesAreMinusTheGradientOfTheContactEnergy) {
  const Model m = model_from_yaml(R"(
gravity: [0, 0, 0]
cloth: {particles: [2, 1], size: [0.1, 0.1], center: [0, 1.004, 0], pinned: none}
spheres: [{center: [0.02, 0, 0], radius: 1.0}]
ground: {height: 0.997}
collision: {model: barrier}
)");
  const State s = initial_state(m);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, m.num_bodies());
  add_barrier_forces(m, s.x, s.v, s.inv_mass, false, f);
  EXPECT_EQ(barrier_contact_count(m, s.x, s.inv_mass), 4);  // each particle: the sphere and the ground
  const double e = 1e-9;
  for (int i = 0; i < m.num_particles; ++i)
    for (int k = 0; k < 3; ++k) {
      Eigen::Matrix3Xd xp = s.x, xm = s.x;
      xp(k, i) += e, xm(k, i) -= e;
      const double fd = -(barrier_potential(m, xp) - barrier_potential(m, xm)) / (2 * e);
      EXPECT_NEAR(f(k, i), fd, 1e-5 * f.norm()) << i << "," << k;
    }
  EXPECT_EQ(f.col(2).norm(), 0.0);  // the kinematic sphere is not pushed
}

// The particle's positions at 30 times through (0, T] from `kind` at step h.
std::vector<Eigen::Vector3d> drop(IntegratorKind kind, double h, double T) {
  const Model m = model_from_yaml(kDrop);
  clothsim::Run run(m, kind, h);
  std::vector<Eigen::Vector3d> out;
  for (int k = 1; k <= 30; ++k) {
    EXPECT_TRUE(run.advance_to(k * T / 30));
    out.push_back(run.state().x.col(0));
  }
  return out;
}

// The largest error over the trajectory (a single time's error can pass near zero).
TEST(BarrierModel, Rk4KeepsItsFourthOrderThroughAContact) {
  const double T = 0.3;  // enters the barrier at ~0.1 s, turns at ~0.15 s, leaves at ~0.2 s
  const std::vector<Eigen::Vector3d> reference = drop(IntegratorKind::Rk4, T / 38400, T);
  double error[4] = {0, 0, 0, 0};
  const double hs[4] = {T / 600, T / 1200, T / 2400, T / 4800};  // (T / 300: 4.85, before the asymptote)
  for (int i = 0; i < 4; ++i) {
    const std::vector<Eigen::Vector3d> run = drop(IntegratorKind::Rk4, hs[i], T);
    for (std::size_t k = 0; k < run.size(); ++k) error[i] = std::max(error[i], (run[k] - reference[k]).norm());
  }
  for (int i = 0; i < 3; ++i) {
    const double order = std::log2(error[i] / error[i + 1]);
    EXPECT_NEAR(order, 4.0, 0.25) << "errors " << error[0] << " " << error[1] << " " << error[2] << " " << error[3];
  }
  // It did touch: the barrier turned it round.
  const Model m = model_from_yaml(kDrop);
  clothsim::Run run(m, IntegratorKind::Rk4, T / 1200);
  double closest = INFINITY;
  for (int k = 1; k <= 300; ++k) {
    run.advance_to(k * T / 300);
    closest = std::min(closest, smallest_barrier_distance(m, run.state().x, run.state().inv_mass));
  }
  EXPECT_LT(closest, 0.025);
  EXPECT_GT(closest, 0.0);
}

TEST(BarrierModel, SymplecticEulerKeepsTheEnergyOfABounce) {
  const Model m = model_from_yaml(kDrop);
  clothsim::Run run(m, IntegratorKind::SymplecticEuler, 1e-5);
  const double start = compute_energies(m, run.state()).total();
  double worst = 0.0, largest_contact = 0.0;
  for (int k = 1; k <= 30; ++k) {
    ASSERT_TRUE(run.advance_to(k * 0.01));
    const Energies e = compute_energies(m, run.state());
    worst = std::max(worst, std::abs(e.total() - start));
    largest_contact = std::max(largest_contact, e.contact);
  }
  EXPECT_GT(largest_contact, 0.01 * std::abs(start));  // the barrier held energy at some frame
  EXPECT_LT(worst, 1e-3 * std::abs(start));
}

// Cloth falling onto a dynamic sphere in zero gravity: what the cloth loses the sphere gains.
const char* kDynamic = R"(
gravity: [0, 0, 0]
cloth: {particles: [4, 4], size: [0.6, 0.6], center: [0, 1.03, 0], pinned: none, initial_velocity: [0, -1, 0],
        springs: {structural: {stiffness: 2000, damping: 5}}}
spheres: [{center: [0, 0, 0], radius: 1.0, kinematic: false, mass: 5}]
collision: {model: barrier}
)";

Eigen::Vector3d momentum(const Model& m, const State& s) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.num_bodies(); ++i) p += m.mass[i] * s.v.col(i);
  return p;
}

TEST(BarrierModel, ADynamicSphereTakesTheOppositeImpulse) {
  const Model m = model_from_yaml(kDynamic);
  for (IntegratorKind kind : {IntegratorKind::Rk4, IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitEuler,
                              IntegratorKind::Vbd}) {
    clothsim::Run run(m, kind, 1e-3);
    const Eigen::Vector3d before = momentum(m, run.state());
    ASSERT_TRUE(run.advance_to(0.1)) << integrator_name(kind);
    EXPECT_LT(run.state().v(1, m.sphere_body(0)), -0.01) << integrator_name(kind);  // pushed down
    // implicit_euler and vbd conserve it at their solution: to their solves' residual (1e-6 relative).
    const bool solved = kind == IntegratorKind::Vbd || kind == IntegratorKind::ImplicitEuler;
    const double tolerance = solved ? 1e-5 : 1e-9;
    EXPECT_LT((momentum(m, run.state()) - before).norm(), tolerance * before.norm()) << integrator_name(kind);
  }
}

// A cloth thrown fast at a sphere and the ground at a frame-sized step.
const char* kThrow = R"(
cloth: {particles: [6, 6], size: [1, 1], center: [0, 1.3, 0], pinned: none, initial_velocity: [0, -6, 0],
        springs: {structural: {stiffness: 20000, damping: 10}, shear: {stiffness: 20000, damping: 10}}}
spheres: [{center: [0, 0, 0], radius: 1.0, velocity: [0, 0, 0], motion: [{t: 0.1, velocity: [2, 0, 0]}]}]
ground: {height: -1.0}
collision: {model: barrier, friction_velocity: 0.01}
)";

TEST(BarrierModel, ImplicitEulerAndVbdNeverLetADistanceReachZero) {
  for (const std::string friction : {"0", "0.4"}) {
    const Model m = model_from_yaml(kThrow, {"spheres.0.friction=" + friction, "ground.friction=" + friction});
    for (IntegratorKind kind : {IntegratorKind::ImplicitEuler, IntegratorKind::Vbd}) {
      clothsim::Run run(m, kind, 1.0 / 60);
      for (int k = 1; k <= 30; ++k) {
        ASSERT_TRUE(run.advance_to(k / 60.0)) << integrator_name(kind);
        EXPECT_GT(smallest_barrier_distance(m, run.state().x, run.state().inv_mass), 0.0)
            << integrator_name(kind) << " step " << k << " friction " << friction;
      }
      if (kind == IntegratorKind::ImplicitEuler) {
        EXPECT_EQ(run.totals().unconverged_steps, 0) << friction;
      }
    }
  }
}

// Backward Euler with static colliders only dissipates: its energy never rises.
TEST(BarrierModel, ImplicitEulerNeverGainsEnergyWithStaticColliders) {
  const Model m = model_from_yaml(kThrow, {"spheres.0.motion=[]", "spheres.0.friction=0.3"});
  clothsim::Run run(m, IntegratorKind::ImplicitEuler, 1.0 / 60);
  double last = compute_energies(m, run.state()).total();
  for (int k = 1; k <= 60; ++k) {
    ASSERT_TRUE(run.advance_to(k / 60.0));
    const double e = compute_energies(m, run.state()).total();
    EXPECT_LE(e, last + 1e-9 * std::abs(last)) << "step " << k;
    last = e;
  }
  EXPECT_EQ(run.totals().unconverged_steps, 0);
}

// The implicit family at a frame-sized step: every end point outside, also where a method
// extrapolates its end from an earlier stage (implicit_midpoint, generalized_alpha: the barrier
// acts at the end point, implicit/step_form.h), and every step converged.
TEST(BarrierModel, TheImplicitFamilyNeverLetsADistanceReachZero) {
  for (const std::string friction : {"0", "0.4"}) {
    const Model m = model_from_yaml(kThrow, {"spheres.0.friction=" + friction, "ground.friction=" + friction});
    for (IntegratorKind kind : {IntegratorKind::ImplicitMidpoint, IntegratorKind::Newmark,
                                IntegratorKind::GeneralizedAlpha, IntegratorKind::Bdf2}) {
      clothsim::Run run(m, kind, 1.0 / 60);
      for (int k = 1; k <= 30; ++k) {
        ASSERT_TRUE(run.advance_to(k / 60.0)) << integrator_name(kind);
        EXPECT_GT(smallest_barrier_distance(m, run.state().x, run.state().inv_mass), 0.0)
            << integrator_name(kind) << " step " << k << " friction " << friction;
      }
      EXPECT_EQ(run.totals().unconverged_steps, 0) << integrator_name(kind) << " friction " << friction;
    }
  }
}

}  // namespace
}  // namespace clothsim
