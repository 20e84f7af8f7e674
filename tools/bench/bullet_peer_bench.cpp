// A peer users compare with: Bullet's btSoftBody on the drape's grids, beside clothsim on the
// same scene, in CPU time per simulated second (docs: BENCHMARKS.md, "A peer: Bullet").
//   build/tools/bench/bullet_peer_benchmarks
// Built only where CMake finds Bullet (libbullet-dev).
//
// The scene is drape.yaml's first second, resized to N x N: a 4 m square cloth of 1 kg
// particles, corners pinned, falling onto a static ball of radius 1 m with the ground 2 m
// below it (the drape's ball starts moving at t = 1 s, so the first second is the same scene
// in both). Same topology: Bullet's patch with its diagonals (clothsim's structural and shear
// springs) and bending links between second neighbours (clothsim's bend springs).
//
// Not the same physics: Bullet's links are position constraints, relaxed by Gauss-Seidel a
// fixed number of times per step (piterations) with a stiffness fraction kLST in [0, 1],
// not springs with a stiffness in N/m, and without dampers; it integrates in single
// precision at a fixed step. The mapping used: kLST = 1 (its stiffest links, the nearest to
// clothsim's k = 2e4 N/m springs, which stretch 0.1-0.2 % under the cloth's weight at rest),
// Bullet's defaults otherwise (piterations 1, step 1/60 s), and the same at 4 iterations and
// 1/240 s, the settings users raise when Bullet's cloth stretches. The collision margin is
// the drape's 0.01 m.
//
// Each iteration simulates the scene's first second from its initial state (the setup is not
// timed). Counters: cpu_per_sim_s, CPU seconds per simulated second (the figure to compare),
// the step, and centre_y, the height of the cloth's centre particle at t = 1 s (a check that
// both cloths ended on the ball, whose top is at y = 1 m); for clothsim also unconverged, the
// implicit steps that missed the Newton tolerance (a method is only "cheapest" at 0).
#include <benchmark/benchmark.h>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <memory>

#include "bench_models.h"
#include "core/simulation.h"

namespace clothsim {
namespace {

constexpr double kSimulated = 1.0;  // s: the drape's ball is still until t = 1 s

// One Bullet world holding the drape's cloth, ball and ground.
struct BulletDrape {
  btSoftBodyRigidBodyCollisionConfiguration collision;
  btCollisionDispatcher dispatcher{&collision};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &collision};
  btSphereShape ball_shape{1.0f};
  btStaticPlaneShape ground_shape{btVector3(0, 1, 0), -2.0f};
  std::unique_ptr<btRigidBody> ball, ground;
  btSoftBody* cloth = nullptr;  // owned by the world's soft body list, deleted below

  BulletDrape(int n, int iterations) {
    world.setGravity(btVector3(0, -9.8f, 0));
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = btVector3(0, -9.8f, 0);
    info.m_sparsesdf.Initialize();
    ball = std::make_unique<btRigidBody>(0.0f, nullptr, &ball_shape);  // mass 0: static
    ground = std::make_unique<btRigidBody>(0.0f, nullptr, &ground_shape);
    world.addRigidBody(ball.get());
    world.addRigidBody(ground.get());

    // The drape's cloth: centre (0, 1, 0), 4 m square in the xz plane, corners pinned
    // (fixeds 1 + 2 + 4 + 8), diagonals generated (shear), bending links at distance 2.
    cloth = btSoftBodyHelpers::CreatePatch(info, btVector3(-2, 1, -2), btVector3(2, 1, -2),
                                           btVector3(-2, 1, 2), btVector3(2, 1, 2), n, n,
                                           1 + 2 + 4 + 8, true);
    cloth->m_materials[0]->m_kLST = 1.0f;
    cloth->generateBendingConstraints(2, cloth->m_materials[0]);
    cloth->m_cfg.piterations = iterations;
    cloth->getCollisionShape()->setMargin(0.01f);
    for (int i = 0; i < cloth->m_nodes.size(); ++i)
      if (cloth->m_nodes[i].m_im != 0) cloth->setMass(i, 1.0f);  // 1 kg particles, pins kept
    world.addSoftBody(cloth);
  }
  ~BulletDrape() {
    world.removeSoftBody(cloth);
    delete cloth;
    world.removeRigidBody(ball.get());
    world.removeRigidBody(ground.get());
  }
  BulletDrape(const BulletDrape&) = delete;
  BulletDrape& operator=(const BulletDrape&) = delete;
};

// Args: N, piterations, steps per second.
void BM_BulletSoftBody(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const int iterations = static_cast<int>(st.range(1));
  const int rate = static_cast<int>(st.range(2));
  const btScalar h = 1.0f / static_cast<btScalar>(rate);
  double cpu = 0.0, centre_height = 0.0;
  for (auto _ : st) {
    st.PauseTiming();
    auto drape = std::make_unique<BulletDrape>(n, iterations);
    st.ResumeTiming();
    const double start = thread_cpu_seconds();
    for (int k = 0; k < static_cast<int>(kSimulated * rate); ++k) drape->world.stepSimulation(h, 1, h);
    cpu += thread_cpu_seconds() - start;
    st.PauseTiming();
    const int centre = (n / 2) * n + n / 2;
    centre_height = drape->cloth->m_nodes[centre].m_x.y();
    drape.reset();
    st.ResumeTiming();
  }
  st.counters["cpu_per_sim_s"] = benchmark::Counter(cpu / kSimulated, benchmark::Counter::kAvgIterations);
  st.counters["dt"] = 1.0 / rate;
  st.counters["centre_y"] = centre_height;
  st.SetLabel("Bullet btSoftBody, float, position constraints");
}
BENCHMARK(BM_BulletSoftBody)
    ->Args({25, 1, 60})->Args({25, 4, 240})->Args({64, 1, 60})->Args({64, 4, 240})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

// Args: N, step in microseconds (or 0 for 1/60 s).
void clothsim_run(benchmark::State& st, IntegratorKind kind) {
  const Model model = bench::drape_sheet(static_cast<int>(st.range(0)));
  const double dt = st.range(1) > 0 ? 1e-6 * static_cast<double>(st.range(1)) : 1.0 / 60.0;
  double cpu = 0.0, centre_height = 0.0;
  bool stable = true;
  std::int64_t unconverged = 0;
  for (auto _ : st) {
    Run run(model, kind, dt);
    stable = run.advance_to(kSimulated) && stable;
    cpu += run.totals().cpu_seconds;
    unconverged = run.totals().unconverged_steps;
    const int n = model.grid_nx;
    centre_height = run.state().x(1, (n / 2) * n + n / 2);
  }
  if (!stable) st.SkipWithError("diverged: not a stable step for this sheet");
  st.counters["cpu_per_sim_s"] = benchmark::Counter(cpu / kSimulated, benchmark::Counter::kAvgIterations);
  st.counters["dt"] = dt;
  st.counters["centre_y"] = centre_height;
  st.counters["unconverged"] = static_cast<double>(unconverged);
  st.SetLabel("clothsim, double, springs and dampers");
}

// Symplectic Euler at its largest stable step: clothsim stability over the first second
// finds 2.73e-4 s (25 x 25) and 2.5e-4 s stable, 2.7e-4 s diverging (64 x 64).
void BM_ClothsimSymplecticAtLimit(benchmark::State& st) { clothsim_run(st, IntegratorKind::SymplecticEuler); }
BENCHMARK(BM_ClothsimSymplecticAtLimit)->Args({25, 250})->Args({64, 250})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ClothsimImplicitAt60Hz(benchmark::State& st) { clothsim_run(st, IntegratorKind::ImplicitEuler); }
BENCHMARK(BM_ClothsimImplicitAt60Hz)->Args({25, 0})->Args({64, 0})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

// One step per 30 Hz frame: every step converges on both sheets (the unconverged counter),
// and at 25 x 25 it is clothsim's cheapest method here.
void BM_ClothsimImplicitAt30Hz(benchmark::State& st) { clothsim_run(st, IntegratorKind::ImplicitEuler); }
BENCHMARK(BM_ClothsimImplicitAt30Hz)->Args({25, 33333})->Args({64, 33333})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace clothsim
