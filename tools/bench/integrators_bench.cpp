// Cost of one step of each integrator on N x N drape sheets (the shipped drape scene's
// cloth, springs, ball and ground, resized), to be read as ratios to a symplectic Euler
// step, plus backward Euler at a frame-rate step (h = 1/240 s) where it earns its cost.
//   build/tools/bench/clothsim_benchmarks --benchmark_filter='IntegratorStep|ImplicitEulerAt240Hz'
// Each iteration is one clothsim::step() (integrate, then collisions and events, as users
// run it) from the state the previous iteration left, at the scene's dt (1e-4 s). Counters
// per step: force_evals, and for implicit_euler newton and cg iterations.
#include <benchmark/benchmark.h>

#include "bench_models.h"
#include "core/run/simulation.h"
#include "core/model/state.h"

namespace clothsim {
namespace {

void run_steps(benchmark::State& st, const Model& m, IntegratorKind kind, double h) {
  const bool newton = integrator_info(kind).iterations == IterationControl::Newton;
  State s = initial_state(m);
  Workspace ws;
  double force_evals = 0, newton_iterations = 0, cg = 0, unconverged = 0;
  for (auto _ : st) {
    const StepStats stats = step(m, s, kind, h, ws).stats;
    force_evals += stats.force_evals;
    newton_iterations += stats.newton_iterations;
    cg += stats.cg_iterations;
    unconverged += stats.converged ? 0.0 : 1.0;
    benchmark::DoNotOptimize(s.x.data());
  }
  if (!s.x.allFinite()) st.SkipWithError("the state went non-finite: the step is unstable here");
  const auto per_step = benchmark::Counter::kAvgIterations;
  st.counters["force_evals"] = benchmark::Counter(force_evals, per_step);
  if (newton) {
    st.counters["newton"] = benchmark::Counter(newton_iterations, per_step);
    st.counters["cg"] = benchmark::Counter(cg, per_step);
    st.counters["unconverged"] = benchmark::Counter(unconverged, per_step);
  }
  st.counters["particles"] = m.num_particles;
}

void BM_IntegratorStep(benchmark::State& st, const char* name) {
  const Model m = bench::drape_sheet(static_cast<int>(st.range(0)));
  run_steps(st, m, bench::method(name), m.dt);
}
BENCHMARK_CAPTURE(BM_IntegratorStep, symplectic_euler, "symplectic_euler")
    ->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntegratorStep, explicit_euler, "explicit_euler")
    ->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntegratorStep, midpoint, "midpoint")
    ->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntegratorStep, rk4, "rk4")
    ->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_IntegratorStep, implicit_euler, "implicit_euler")
    ->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);

// The same steps for every integrator: the drape's first second (10 000 steps of 1e-4 s: the
// fall, the impact and the settling on the ball), so the ratios compare one stretch of the
// scene. BM_IntegratorStep runs as many steps as the benchmark library picks for each, so a
// cheap integrator steps on through the ball's pushes while a dear one stays in the first
// second, and its ratios mix the two.
void BM_IntegratorFirstSecond(benchmark::State& st, const char* name) {
  const Model m = bench::drape_sheet(static_cast<int>(st.range(0)));
  run_steps(st, m, bench::method(name), m.dt);
}
BENCHMARK_CAPTURE(BM_IntegratorFirstSecond, symplectic_euler, "symplectic_euler")
    ->Arg(25)->Arg(64)->Unit(benchmark::kMicrosecond)->Iterations(10000);
BENCHMARK_CAPTURE(BM_IntegratorFirstSecond, implicit_euler, "implicit_euler")
    ->Arg(25)->Arg(64)->Unit(benchmark::kMicrosecond)->Iterations(10000);
// The Verlet family at the same steps: one force pass a step for velocity_verlet (its last pass
// is the next step's first), three for yoshida4.
BENCHMARK_CAPTURE(BM_IntegratorFirstSecond, velocity_verlet, "velocity_verlet")
    ->Arg(25)->Arg(64)->Unit(benchmark::kMicrosecond)->Iterations(10000);
BENCHMARK_CAPTURE(BM_IntegratorFirstSecond, yoshida4, "yoshida4")
    ->Arg(25)->Arg(64)->Unit(benchmark::kMicrosecond)->Iterations(10000);

// The implicit family against backward Euler at one step per frame on the barrier drape (the
// contact every one of them takes): the first 2 s at 1/60 s, 120 steps from its start.
void BM_ImplicitFamilyAtFrameRate(benchmark::State& st, const char* name) {
  const Model m = bench::smooth_drape_sheet(static_cast<int>(st.range(0)));
  run_steps(st, m, bench::method(name), 1.0 / 60.0);
}
BENCHMARK_CAPTURE(BM_ImplicitFamilyAtFrameRate, implicit_euler, "implicit_euler")
    ->Arg(25)->Unit(benchmark::kMillisecond)->Iterations(120);
BENCHMARK_CAPTURE(BM_ImplicitFamilyAtFrameRate, implicit_midpoint, "implicit_midpoint")
    ->Arg(25)->Unit(benchmark::kMillisecond)->Iterations(120);
BENCHMARK_CAPTURE(BM_ImplicitFamilyAtFrameRate, newmark, "newmark")
    ->Arg(25)->Unit(benchmark::kMillisecond)->Iterations(120);
BENCHMARK_CAPTURE(BM_ImplicitFamilyAtFrameRate, generalized_alpha, "generalized_alpha")
    ->Arg(25)->Unit(benchmark::kMillisecond)->Iterations(120);
BENCHMARK_CAPTURE(BM_ImplicitFamilyAtFrameRate, bdf2, "bdf2")
    ->Arg(25)->Unit(benchmark::kMillisecond)->Iterations(120);

// Backward Euler (Newton + PCG, the scene's default tolerances) at h = 1/240 s on 64 x 64,
// 417 times the drape's dt; the explicit methods are unstable there. Iterations start from
// the drape's initial state (cloth resting on the ball) and follow its fall.
void BM_ImplicitEulerAt240Hz(benchmark::State& st) {
  const Model m = bench::drape_sheet(static_cast<int>(st.range(0)));
  run_steps(st, m, kBackwardEuler, 1.0 / 240.0);
}
BENCHMARK(BM_ImplicitEulerAt240Hz)->Arg(64)->Unit(benchmark::kMillisecond)->Iterations(120);

}  // namespace
}  // namespace clothsim
