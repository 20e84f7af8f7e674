// Engine throughput: the spring force pass (springs/s; SIMD and scalar) and one full step of
// symplectic Euler (forces + integrate + collisions + events) on N x N drape sheets.
//   build/tools/bench/clothsim_benchmarks --benchmark_filter='SpringForces|SymplecticStep'
#include <benchmark/benchmark.h>

#include "bench_models.h"
#include "core/model/forces.h"
#include "core/run/simulation.h"
#include "core/springs/spring_kernels.h"
#include "core/model/state.h"

namespace clothsim {
namespace {

// One spring force pass on a perturbed sheet: the default path (the SIMD kernel over the
// grid's stencil families, labelled with the Highway target it runs) and the scalar reference
// loop, side by side in one binary so their ratio is measured under the same conditions.
void spring_forces(benchmark::State& st, bool simd) {
  const Model m = bench::drape_sheet(static_cast<int>(st.range(0)));
  State s = initial_state(m);
  s.x += 0.01 * Eigen::Matrix3Xd::Random(3, m.num_bodies());  // every spring stretched a little
  s.v = Eigen::Matrix3Xd::Random(3, m.num_bodies());
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, m.num_bodies());
  for (auto _ : st) {
    f.setZero();
    if (simd) {
      accumulate_spring_forces(m, s.x, s.v, f);
    } else {
      accumulate_spring_forces_scalar(m.springs, s.x, s.v, f);
    }
    benchmark::DoNotOptimize(f.data());
    benchmark::ClobberMemory();
  }
  if (simd) st.SetLabel(spring_kernel_target());
  st.counters["springs"] = static_cast<double>(m.springs.size());
  st.counters["springs/s"] = benchmark::Counter(static_cast<double>(m.springs.size()),
                                                benchmark::Counter::kIsIterationInvariantRate);
}
void BM_SpringForces(benchmark::State& st) { spring_forces(st, true); }
void BM_SpringForcesScalar(benchmark::State& st) { spring_forces(st, false); }
BENCHMARK(BM_SpringForces)->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SpringForcesScalar)->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);

void BM_SymplecticStep(benchmark::State& st) {
  const Model m = bench::drape_sheet(static_cast<int>(st.range(0)));
  State s = initial_state(m);
  Workspace ws;
  const IntegratorKind symplectic = bench::method("symplectic_euler");
  for (auto _ : st) {
    step(m, s, symplectic, m.dt, ws);
    benchmark::DoNotOptimize(s.x.data());
  }
  st.counters["springs/s"] = benchmark::Counter(static_cast<double>(m.springs.size()),
                                                benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SymplecticStep)->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace clothsim

BENCHMARK_MAIN();
