// A peer for projective dynamics' prefactored solve: SuiteSparse's CHOLMOD (supernodal
// Cholesky, BLAS from whichever libblas.so.3 Debian's alternatives select: OpenBLAS when
// libopenblas0 is installed) beside clothsim's own, on the same matrix (BENCHMARKS.md, "Sparse
// direct solves: CHOLMOD against clothsim's").
//   build/tools/bench/cholmod_peer_benchmarks
// Built only where CMake finds CHOLMOD (libsuitesparse-dev).
//
// The matrix: PD's global matrix of the drape's sheet at N x N and 1/60 s (M/h^2 plus the
// springs' Laplacian, pinned corners removed), as clothsim orders it (Eigen's AMD). clothsim
// factors it with Eigen's SimplicialLDLT and repacks L by supernodes (pd_supernodes.h) for its
// SIMD solve, which does x, y and z in one sweep (pd_solve_kernels.h); CHOLMOD analyses it
// (its own ordering choice), factors it supernodally and solves the three columns with
// cholmod_solve2 (its workspace reused, no allocation per solve). A solve runs every PD
// iteration; a factorization only when the step or the pins change.
#include <benchmark/benchmark.h>
#include <suitesparse/cholmod.h>

#include <Eigen/SparseCore>
#include <memory>
#include <string>

#include "cholmod_support.h"
#include "core/solvers/pd_kernels.h"
#include "core/solvers/pd_solve_kernels.h"
#include "core/solvers/step_problem.h"
#include "core/model/state.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

using namespace clothsim;

namespace {

struct Sheet {
  Model model;
  StepProblem problem;
  Eigen::VectorXd inv_mass;
  PdFactor factor;                        // clothsim's, factored once
  Eigen::SparseMatrix<double> lower;      // the permuted matrix's lower triangle, for CHOLMOD
  Eigen::Matrix4Xd rhs;                   // x, y, z and a zero pad per row
  Supernodes exact;                       // the factor's panels in double, to check CHOLMOD's answer
};

std::unique_ptr<Sheet> sheet(int n) {
  auto s = std::make_unique<Sheet>();
  const std::string side = std::to_string(n);
  s->model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                    {"cloth.particles=[" + side + "," + side + "]"}));
  const State state = initial_state(s->model);
  s->inv_mass = state.inv_mass;
  build_step_problem(s->model, state, 1.0 / 60.0, s->problem);
  pd_prepare_factor(s->model, s->problem, s->inv_mass, s->factor);
  // The matrix as clothsim factored it (P A P^T = L D L^T), rebuilt from its factor.
  const Eigen::SparseMatrix<double> L = s->factor.ldlt.matrixL();
  const Eigen::SparseMatrix<double> LD = L * s->factor.ldlt.vectorD().asDiagonal();
  const Eigen::SparseMatrix<double> A = LD * Eigen::SparseMatrix<double>(L.transpose());
  s->lower = A.triangularView<Eigen::Lower>();
  s->lower.makeCompressed();
  s->rhs = Eigen::Matrix4Xd::Random(4, s->factor.ldlt.rows());
  s->rhs.row(3).setZero();
  const auto& Lc = s->factor.ldlt.matrixL().nestedExpression();
  s->exact = supernodes_of(static_cast<std::size_t>(Lc.cols()), Lc.outerIndexPtr(), Lc.innerIndexPtr(),
                           Lc.valuePtr(), s->factor.ldlt.vectorD().data(), 0.3);
  return s;
}

struct Cholmod : bench::CholmodCommon {
  Cholmod() { c.supernodal = CHOLMOD_SUPERNODAL; }
};

void BM_PdFactor_Clothsim(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  for (auto _ : st) {
    PdFactor f;  // a fresh one: ordering, symbolic and numeric factorization, supernode repacking
    pd_prepare_factor(s->model, s->problem, s->inv_mass, f);
    benchmark::DoNotOptimize(f.panels.value.data());
  }
  st.counters["L_entries"] = static_cast<double>(s->factor.panels.entries);
}

void BM_PdFactor_Cholmod(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  Cholmod cm;
  cholmod_sparse a = bench::cholmod_view(s->lower);
  double entries = 0.0;
  for (auto _ : st) {
    cholmod_factor* L = cholmod_analyze(&a, &cm.c);
    cholmod_factorize(&a, L, &cm.c);
    entries = cm.c.lnz;
    cholmod_free_factor(&L, &cm.c);
  }
  if (cm.c.status != CHOLMOD_OK) st.SkipWithError("CHOLMOD failed");
  st.counters["L_entries"] = entries - static_cast<double>(s->lower.rows());  // (strictly lower, as clothsim's)
}

void BM_PdSolve_Clothsim(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  const Eigen::Matrix4Xf rhs = s->rhs.cast<float>();  // PD's solve runs on float panels (pd_kernels.h)
  Eigen::Matrix4Xf z = rhs;
  for (auto _ : st) {
    z = rhs;
    ldlt_solve_padded(s->factor.panels, z.data());
    benchmark::DoNotOptimize(z.data());
  }
}

void BM_PdSolve_Cholmod(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  Cholmod cm;
  cholmod_sparse a = bench::cholmod_view(s->lower);
  cholmod_factor* L = cholmod_analyze(&a, &cm.c);
  cholmod_factorize(&a, L, &cm.c);
  const Eigen::Index n = s->lower.rows();
  cholmod_dense* b = cholmod_allocate_dense(static_cast<std::size_t>(n), 3, static_cast<std::size_t>(n), CHOLMOD_REAL, &cm.c);
  Eigen::Map<Eigen::MatrixXd>(static_cast<double*>(b->x), n, 3) = s->rhs.topRows<3>().transpose();
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
  for (auto _ : st) {
    cholmod_solve2(CHOLMOD_A, L, b, nullptr, &x, nullptr, &y, &e, &cm.c);
    benchmark::DoNotOptimize(x->x);
  }
  // The same answer as clothsim's solve (both exact factorizations of one matrix).
  Eigen::Matrix4Xd z = s->rhs;
  ldlt_solve_padded(s->exact, z.data());
  const double gap = (Eigen::Map<Eigen::MatrixXd>(static_cast<double*>(x->x), n, 3) - z.topRows<3>().transpose())
                         .cwiseAbs()
                         .maxCoeff();
  st.counters["max_gap"] = gap;
  if (!(gap < 1e-9)) st.SkipWithError("CHOLMOD's solve differs from clothsim's");
  cholmod_free_dense(&x, &cm.c);
  cholmod_free_dense(&y, &cm.c);
  cholmod_free_dense(&e, &cm.c);
  cholmod_free_dense(&b, &cm.c);
  cholmod_free_factor(&L, &cm.c);
}

}  // namespace

BENCHMARK(BM_PdFactor_Clothsim)->Arg(32)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PdFactor_Cholmod)->Arg(32)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PdSolve_Clothsim)->Arg(32)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PdSolve_Cholmod)->Arg(32)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMicrosecond);
