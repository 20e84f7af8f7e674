// The pieces of implicit Euler's linear solves, to calibrate the preconditioner's choice
// (cholesky_preconditioner.h counts a factorisation and a factored solve in block-Jacobi PCG
// iterations; the counters here print those estimates beside the timings):
//   build/tools/bench/clothsim_benchmarks --benchmark_filter='Solver'
// The matrix is the projected step Hessian at the scene's initial state, h = 1/60 s, on
// stiff.yaml (15 x 15), the drape resized to 64 x 64 and the drape's own 25 x 25 (arg 2: what
// core/work_units.h's table is calibrated on). One block-Jacobi iteration is about
// one BM_SolverBlockMatVec plus one BM_SolverJacobi.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>

#include "bench_models.h"
#include "least_cpu.h"
#include "core/implicit/sparse_system.h"
#include "core/integrators/integrator.h"
#include "core/solvers/pd_solve_kernels.h"
#include "core/solvers/solver_cache.h"
#include "core/implicit/step_potential.h"
#include "core/linear/cholesky_preconditioner.h"
#include "core/model/state.h"
#include "scene/build_model.h"

namespace clothsim {
namespace {

struct System {
  Model model;
  SpringBlockMatrix A;
  Eigen::Matrix3Xd r;
};

System system(int which) {
  System s{which == 0 ? build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml", {}))
                      : bench::drape_sheet(which == 1 ? 64 : 25),
           {}, {}};
  const State st = initial_state(s.model);
  std::vector<double> length;
  step_lengths(s.model, st.x, length);
  build_pattern(s.model, s.A);
  assemble_step_hessian(s.model, st.inv_mass, 1.0 / 60.0, length, st.x, HessianBlocks::Projected, s.A);
  s.r = Eigen::Matrix3Xd::Random(3, s.model.num_bodies());
  return s;
}

const char* name(int which) { return which == 0 ? "stiff 15x15" : which == 1 ? "drape 64x64" : "drape 25x25"; }

void BM_SolverBlockMatVec(benchmark::State& st) {
  const System s = system(static_cast<int>(st.range(0)));
  Eigen::Matrix3Xd y;
  for (auto _ : st) {
    multiply(s.A, s.r, y);
    benchmark::DoNotOptimize(y.data());
  }
  st.SetLabel(name(static_cast<int>(st.range(0))));
}
BENCHMARK(BM_SolverBlockMatVec)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_SolverJacobi(benchmark::State& st) {
  const System s = system(static_cast<int>(st.range(0)));
  Eigen::Matrix3Xd z(3, s.r.cols());
  for (auto _ : st) {
    for (Eigen::Index i = 0; i < s.r.cols(); ++i) z.col(i) = s.A.diag_inverse[i] * s.r.col(i);
    benchmark::DoNotOptimize(z.data());
  }
  st.SetLabel(name(static_cast<int>(st.range(0))));
}
BENCHMARK(BM_SolverJacobi)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_SolverAssembly(benchmark::State& st) {
  System s = system(static_cast<int>(st.range(0)));
  const State start = initial_state(s.model);
  std::vector<double> length;
  step_lengths(s.model, start.x, length);
  for (auto _ : st) {
    assemble_step_hessian(s.model, start.inv_mass, 1.0 / 60.0, length, start.x, HessianBlocks::Exact, s.A);
    benchmark::DoNotOptimize(s.A.diag.data());
  }
  st.SetLabel(name(static_cast<int>(st.range(0))));
}
BENCHMARK(BM_SolverAssembly)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_SolverFactorize(benchmark::State& st) {
  const System s = system(static_cast<int>(st.range(0)));
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  for (auto _ : st) benchmark::DoNotOptimize(factor.factorize(s.A, VelocityFilter{}));
  st.counters["est_jacobi_iterations"] = factor.factor_cost();
  st.counters["L_blocks"] = static_cast<double>(factor.factor_blocks());
  st.SetLabel(name(static_cast<int>(st.range(0))));
}
BENCHMARK(BM_SolverFactorize)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_SolverFactoredSolve(benchmark::State& st) {
  const System s = system(static_cast<int>(st.range(0)));
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  factor.factorize(s.A, VelocityFilter{});
  Eigen::Matrix3Xd z;
  for (auto _ : st) {
    factor.apply(s.r, z);
    benchmark::DoNotOptimize(z.data());
  }
  st.counters["est_jacobi_iterations"] = factor.solve_cost();
  st.SetLabel(name(static_cast<int>(st.range(0))));
}
BENCHMARK(BM_SolverFactoredSolve)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

// PD's factor: L's strictly lower entries per row, those its supernodes' panels store (their
// zeros included), the supernodes' mean width in columns, the values the panels hold per row
// (their diagonal blocks' unread upper zeros too: memory) and the share of the stored entries
// in panels at least 8 columns wide (the solve's widest step, pd_solve_kernels.cpp).
template <typename T>
void pd_factor_counters(const BasicSupernodes<T>& f, benchmark::State& st) {
  double stored = 0.0, wide = 0.0;
  for (std::size_t s = 0; s < f.size(); ++s) {
    const double w = f.first[s + 1] - f.first[s], m = f.row_start[s + 1] - f.row_start[s];
    stored += w * (w - 1) / 2 + (m - w) * w;
    if (w >= 8) wide += w * (w - 1) / 2 + (m - w) * w;
  }
  st.counters["wide_share"] = wide / stored;
  const double n = static_cast<double>(f.n);
  st.counters["L_per_row"] = static_cast<double>(f.entries) / n;
  st.counters["stored_per_row"] = stored / n;
  st.counters["supernode_width"] = n / static_cast<double>(f.size());
  st.counters["values_per_row"] = static_cast<double>(f.value.size()) / n;
}

const char* const kSolvers[] = {"xpbd", "projective_dynamics", "vbd"};

// One iteration of an iterative solver in spring passes (BENCHMARKS.md, "The iterative
// solvers"): (a step of 55 iterations - a step of 5) / 50 over one symplectic Euler step of
// the same sheet, each the least thread CPU time of its repeats, all in this one process.
// Args: solver (0 xpbd, 1 projective_dynamics, 2 vbd) and the drape's side n.
//   build/tools/bench/clothsim_benchmarks --benchmark_filter='SolverIteration'
void BM_SolverIteration(benchmark::State& st) {
  const IntegratorKind kind = bench::method(kSolvers[st.range(0)]);
  const int n = static_cast<int>(st.range(1));
  Model few = bench::drape_sheet(n), many = few;
  for (Model* m : {&few, &many}) {
    const int it = m == &few ? 5 : 55;
    m->solvers.xpbd.iterations = m->solvers.projective_dynamics.iterations = m->solvers.vbd.iterations = it;
  }
  const State start = initial_state(few);
  Workspace ws;
  State s = start;
  integrate(kind, few, s, 1.0 / 60.0, ws);  // builds the factor or the colouring
  const int repeats = n >= 256 ? 2 : 5;
  double pass = 0.0, per_iteration = 0.0;
  for (auto _ : st) {
    pass = bench::least_cpu_seconds(repeats * 4, [&] {
      s = start;
      integrate(bench::method("symplectic_euler"), few, s, 1e-4, ws);
    });
    const double t5 = bench::least_cpu_seconds(repeats, [&] { s = start, integrate(kind, few, s, 1.0 / 60.0, ws); });
    const double t55 = bench::least_cpu_seconds(repeats, [&] { s = start, integrate(kind, many, s, 1.0 / 60.0, ws); });
    per_iteration = (t55 - t5) / 50.0;
  }
  st.counters["pass_us"] = 1e6 * pass;
  st.counters["iteration_us"] = 1e6 * per_iteration;
  st.counters["passes_per_iteration"] = per_iteration / pass;
  if (integrator_name(kind) == "projective_dynamics") pd_factor_counters(solver_cache(ws).pd.panels, st);
  st.SetLabel(std::string(integrator_name(kind)) + " " + std::to_string(n) + "x" + std::to_string(n));
}
// PD's global solve alone (ldlt_solve_padded, three columns, float panels) on the drape's factor at h = 1/60 s;
void BM_SolverPdSolve(benchmark::State& st) {
  const Model model = bench::drape_sheet(static_cast<int>(st.range(0)));
  State s = initial_state(model);
  Workspace ws;
  integrate(bench::method("projective_dynamics"), model, s, 1.0 / 60.0, ws);
  const PdFactor& f = solver_cache(ws).pd;
  // float: the panels PD keeps (pd_kernels.h, defect correction)
  Eigen::Matrix4Xf b = Eigen::Matrix4Xf::Random(4, f.ldlt.rows()), z;
  b.row(3).setZero();
  for (auto _ : st) {
    z = b;
    ldlt_solve_padded(f.panels, z.data());
    benchmark::DoNotOptimize(z.data());
  }
  pd_factor_counters(f.panels, st);
}
BENCHMARK(BM_SolverPdSolve)->Arg(25)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_SolverIteration)
    ->ArgsProduct({{0, 1, 2}, {25, 64, 256}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothsim
