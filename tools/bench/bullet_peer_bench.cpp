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
// the step, and at t = 1 s: centre_y, the height of the cloth's centre particle (the ball's
// top is at y = 1 m); inside, how deep the deepest particle above the ball (x^2 + z^2 < r^2)
// lies inside its surface, m (negative: all outside; issue 24's criterion is <= 0.02 m);
// strain, the largest |l - l0| / l0 over springs (Bullet: links); strain_ratio, that over
// converged backward Euler's on the same sheet at 1/60 s; meets, 1 when both criteria hold
// (inside <= kReach and strain_ratio <= kStrainRatio: the cloth on the ball, and not held
// there stretched by the post-step projection); for clothsim also unconverged, the implicit
// steps that missed the Newton tolerance, wrong, 1 when the run read WRONG (energy made or
// strain past its bound: core/diagnostics.h), and the iterative solvers' iterations per step
// (a lane NAME@STEP:N of compare and bench).
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
#include <algorithm>
#include <limits>
#include <map>
#include <memory>

#include "bench_models.h"
#include "core/model/diagnostics.h"
#include "core/run/simulation.h"

namespace clothsim {
namespace {

constexpr double kSimulated = 1.0;  // s: the drape's ball is still until t = 1 s
constexpr double kBallRadius = 1.0;  // m, centred at the origin
constexpr double kReach = 0.02;      // m, issue 24's "within 2 cm of the ball"
constexpr double kStrainRatio = 1.5;  // issue 33's: strain within 1.5x converged backward Euler's

// The end strain of converged backward Euler at 1/60 s on the n x n sheet, once per n.
double converged_strain(int n) {
  static std::map<int, double> known;
  const auto found = known.find(n);
  if (found != known.end()) return found->second;
  const Model model = bench::drape_sheet(n);
  Run run(model, kBackwardEuler, 1.0 / 60.0);
  run.advance_to(kSimulated);
  return known[n] = max_strain(model, run.state());
}

// The criterion's counters: strain against converged backward Euler's, and whether both hold.
void criterion_counters(benchmark::State& st, int n, double inside, double strain) {
  const double ratio = strain / converged_strain(n);
  st.counters["strain_ratio"] = ratio;
  st.counters["meets"] = inside <= kReach && ratio <= kStrainRatio ? 1.0 : 0.0;
}

// How deep the deepest of the points above the ball lies inside its surface, m.
template <class Point>
double deepest_inside(int count, const Point& point) {
  double deepest = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i) {
    const Vec3 p = point(i);
    if (p.x() * p.x() + p.z() * p.z() < kBallRadius * kBallRadius && p.y() > 0.0)
      deepest = std::max(deepest, kBallRadius - p.norm());
  }
  return deepest;
}

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
  double cpu = 0.0, centre_height = 0.0, inside = 0.0, strain = 0.0;
  for (auto _ : st) {
    st.PauseTiming();
    auto drape = std::make_unique<BulletDrape>(n, iterations);
    st.ResumeTiming();
    const double start = thread_cpu_seconds();
    for (int k = 0; k < static_cast<int>(kSimulated * rate); ++k) drape->world.stepSimulation(h, 1, h);
    cpu += thread_cpu_seconds() - start;
    st.PauseTiming();
    const int centre = (n / 2) * n + n / 2;
    const btSoftBody& cloth = *drape->cloth;
    centre_height = cloth.m_nodes[centre].m_x.y();
    inside = deepest_inside(cloth.m_nodes.size(), [&](int i) {
      const btVector3& x = cloth.m_nodes[i].m_x;
      return Vec3(x.x(), x.y(), x.z());
    });
    strain = 0.0;
    for (int k = 0; k < cloth.m_links.size(); ++k) {
      const btSoftBody::Link& l = cloth.m_links[k];
      strain = std::max(strain, static_cast<double>(std::abs((l.m_n[0]->m_x - l.m_n[1]->m_x).length() - l.m_rl) / l.m_rl));
    }
    drape.reset();
    st.ResumeTiming();
  }
  st.counters["cpu_per_sim_s"] = benchmark::Counter(cpu / kSimulated, benchmark::Counter::kAvgIterations);
  st.counters["dt"] = 1.0 / rate;
  st.counters["centre_y"] = centre_height;
  st.counters["inside"] = inside;
  st.counters["strain"] = strain;
  criterion_counters(st, n, inside, strain);
  st.SetLabel("Bullet btSoftBody, float, position constraints");
}
BENCHMARK(BM_BulletSoftBody)
    ->Args({25, 1, 60})->Args({25, 4, 240})->Args({64, 1, 60})->Args({64, 4, 240})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

// Args: N, step in microseconds (or 0 for 1/60 s), and for the iterative solvers iterations.
void clothsim_run(benchmark::State& st, const char* name) {
  const IntegratorKind kind = bench::method(name);
  Model model = bench::drape_sheet(static_cast<int>(st.range(0)));
  const double dt = st.range(1) > 0 ? 1e-6 * static_cast<double>(st.range(1)) : 1.0 / 60.0;
  const int iterations = is_iterative_solver(kind) ? static_cast<int>(st.range(2)) : 0;
  if (int* n = iteration_count(model, kind); n && integrator_info(kind).iterations == IterationControl::Solver)
    *n = iterations;
  double cpu = 0.0, centre_height = 0.0, inside = 0.0, strain = 0.0;
  bool stable = true, wrong = false;
  std::int64_t unconverged = 0;
  for (auto _ : st) {
    Run run(model, kind, dt);
    stable = run.advance_to(kSimulated) && stable;
    cpu += run.totals().cpu_seconds;
    unconverged = run.totals().unconverged_steps;
    wrong = run.totals().wrong.has_value();
    const int n = model.grid_nx;
    const State& s = run.state();
    centre_height = s.x(1, (n / 2) * n + n / 2);
    inside = deepest_inside(model.num_particles, [&](int i) { return Vec3(s.x.col(i)); });
    strain = max_strain(model, s);
  }
  if (!stable) st.SkipWithError("diverged: not a stable step for this sheet");
  st.counters["cpu_per_sim_s"] = benchmark::Counter(cpu / kSimulated, benchmark::Counter::kAvgIterations);
  st.counters["dt"] = dt;
  st.counters["centre_y"] = centre_height;
  st.counters["inside"] = inside;
  st.counters["strain"] = strain;
  st.counters["unconverged"] = static_cast<double>(unconverged);
  st.counters["wrong"] = wrong ? 1.0 : 0.0;
  criterion_counters(st, model.grid_nx, inside, strain);
  if (iterations > 0) st.counters["iterations"] = iterations;
  st.SetLabel("clothsim, double, springs and dampers");
}

// Symplectic Euler at its largest stable step: clothsim stability over the first second
// finds 2.73e-4 s (25 x 25) and 2.5e-4 s stable, 2.7e-4 s diverging (64 x 64).
void BM_ClothsimSymplecticAtLimit(benchmark::State& st) { clothsim_run(st, "symplectic_euler"); }
BENCHMARK(BM_ClothsimSymplecticAtLimit)->Args({25, 250})->Args({64, 250})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ClothsimImplicitAt60Hz(benchmark::State& st) { clothsim_run(st, "implicit_euler"); }
BENCHMARK(BM_ClothsimImplicitAt60Hz)->Args({25, 0})->Args({64, 0})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

// One step per 30 Hz frame: every step converges on both sheets (the unconverged counter),
// and at 25 x 25 it is clothsim's cheapest method here.
void BM_ClothsimImplicitAt30Hz(benchmark::State& st) { clothsim_run(st, "implicit_euler"); }
BENCHMARK(BM_ClothsimImplicitAt30Hz)->Args({25, 33333})->Args({64, 33333})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

// The solvers people ship, at one step per 60 Hz frame with few iterations (issue 24): lanes
// xpbd@1/60:N, projective_dynamics@1/60:N, vbd@1/60:N. Contacts are held by every method's
// post-step response, so all keep the cloth on the ball; few iterations leave it stretched
// (the strain counter) and some diverge at 64 x 64.
void BM_ClothsimXpbd(benchmark::State& st) { clothsim_run(st, "xpbd"); }
BENCHMARK(BM_ClothsimXpbd)->Args({25, 0, 1})->Args({25, 0, 4})->Args({64, 0, 2})->Args({64, 0, 3})
    ->Args({64, 0, 4})->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ClothsimProjectiveDynamics(benchmark::State& st) { clothsim_run(st, "projective_dynamics"); }
BENCHMARK(BM_ClothsimProjectiveDynamics)->Args({25, 0, 1})->Args({64, 0, 1})->Args({64, 0, 3})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ClothsimVbd(benchmark::State& st) { clothsim_run(st, "vbd"); }
BENCHMARK(BM_ClothsimVbd)->Args({25, 0, 1})->Args({64, 0, 1})->Args({64, 0, 3})
    ->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace clothsim
