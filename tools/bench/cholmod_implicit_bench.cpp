// CHOLMOD against implicit Euler's own sparse factor (the `cholesky` preconditioner,
// cholesky_preconditioner.h), on the same matrices (BENCHMARKS.md, "Sparse direct solves:
// CHOLMOD against clothsim's", implicit Euler's table):
//   OPENBLAS_NUM_THREADS=1 build/tools/bench/cholmod_implicit_benchmarks
// Built only where CMake finds CHOLMOD (libsuitesparse-dev), as cholmod_peer_bench.cpp.
//
// The matrix: the projected step Hessian M + h^2 K (3N x 3N, SPD) of the refined drape at
// N x N (the same 4 m sheet, particle mass (32/N)^2 kg, `bench --scale`'s rule), h = 1/60 s,
// at the sheet's initial state. Three phases, as the Newton solve meets them: the analysis
// (once per sparsity pattern: ordering and symbolic factor), the numeric factorization
// (repeated as Newton's matrix changes: cholmod_factorize on the kept cholmod_factor) and one
// solve (one PCG iteration's preconditioner: a single 3N right-hand side). CHOLMOD's variants:
// arg 1 = 0 supernodal + AMD, 1 supernodal + METIS, 2 simplicial + AMD, 3 simplicial + METIS.
// CHOLMOD's factorization is timed without filling its CSC values from the blocks, which the
// Newton solve would also pay: the comparison favours CHOLMOD.
#include <benchmark/benchmark.h>
#include <suitesparse/cholmod.h>

#include <Eigen/SparseCore>
#include <memory>
#include <utility>

#include "cholmod_support.h"
#include "core/linear/cholesky_preconditioner.h"
#include "implicit_sheet.h"

using namespace clothsim;

namespace {

// The refined drape's projected step Hessian (implicit_sheet.h) and its lower triangle, scalar.
struct Sheet {
  std::unique_ptr<bench::ImplicitSheet> sheet;
  SpringBlockMatrix& A;
  Eigen::Matrix3Xd& r;                // (3 x B) a right-hand side
  Eigen::SparseMatrix<double> lower;  // (3B x 3B) A's lower triangle, for CHOLMOD
  explicit Sheet(std::unique_ptr<bench::ImplicitSheet> s)
      : sheet(std::move(s)), A(sheet->A), r(sheet->r),
        lower(bench::scalar_matrix<Eigen::ColMajor>(A, bench::Triangle::Lower, true)) {}
};

std::unique_ptr<Sheet> sheet(int n) { return std::make_unique<Sheet>(bench::implicit_sheet(n)); }

struct Cholmod : bench::CholmodCommon {
  explicit Cholmod(int variant) {
    c.supernodal = variant < 2 ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c.nmethods = 1;  // the one ordering asked for, not CHOLMOD's default trial of several
    c.method[0].ordering = variant % 2 == 0 ? CHOLMOD_AMD : CHOLMOD_METIS;
    c.postorder = 1;
  }
};

const char* label(int variant) {
  static const char* names[] = {"supernodal AMD", "supernodal METIS", "simplicial AMD", "simplicial METIS"};
  return names[variant];
}

// One block-Jacobi PCG iteration's two passes (the block mat-vec and the block-diagonal solve):
// the unit the Newton solve's rent-against-buy counts in (newton_solve.h, FactorAccount).
void BM_IeJacobiIteration_Clothsim(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  invert_diagonal(s->A);
  Eigen::Matrix3Xd y, z(3, s->r.cols());
  for (auto _ : st) {
    multiply(s->A, s->r, y);
    for (Eigen::Index i = 0; i < s->r.cols(); ++i) z.col(i) = s->A.diag_inverse[i] * y.col(i);
    benchmark::DoNotOptimize(z.data());
  }
}

void BM_IeAnalyse_Clothsim(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  for (auto _ : st) {
    CholeskyPreconditioner f;
    f.analyse(s->A);
    benchmark::DoNotOptimize(f.factor_blocks());
  }
}

void BM_IeFactorize_Clothsim(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  CholeskyPreconditioner f;
  f.analyse(s->A);
  for (auto _ : st) benchmark::DoNotOptimize(f.factorize(s->A, VelocityFilter{}));
  // L's strictly lower scalar entries: 9 per off-diagonal block and 3 inside each diagonal one.
  st.counters["L_entries"] = 9.0 * static_cast<double>(f.factor_blocks()) + 3.0 * s->A.num_bodies();
  st.counters["est_jacobi_iterations"] = f.factor_cost();
}

void BM_IeSolve_Clothsim(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  CholeskyPreconditioner f;
  f.analyse(s->A);
  f.factorize(s->A, VelocityFilter{});
  Eigen::Matrix3Xd z;
  for (auto _ : st) {
    f.apply(s->r, z);
    benchmark::DoNotOptimize(z.data());
  }
  st.counters["est_jacobi_iterations"] = f.solve_cost();
}

void BM_IeAnalyse_Cholmod(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  const int variant = static_cast<int>(st.range(1));
  Cholmod cm(variant);
  cholmod_sparse a = bench::cholmod_view(s->lower);
  for (auto _ : st) {
    cholmod_factor* L = cholmod_analyze(&a, &cm.c);
    benchmark::DoNotOptimize(L);
    cholmod_free_factor(&L, &cm.c);
  }
  if (cm.c.status != CHOLMOD_OK) st.SkipWithError("CHOLMOD's analysis failed");
  st.SetLabel(label(variant));
}

void BM_IeFactorize_Cholmod(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  const int variant = static_cast<int>(st.range(1));
  Cholmod cm(variant);
  cholmod_sparse a = bench::cholmod_view(s->lower);
  cholmod_factor* L = cholmod_analyze(&a, &cm.c);  // once per pattern, kept
  for (auto _ : st) cholmod_factorize(&a, L, &cm.c);
  if (cm.c.status != CHOLMOD_OK) st.SkipWithError("CHOLMOD's factorization failed");
  st.counters["L_entries"] = cm.c.lnz - static_cast<double>(s->lower.rows());  // strictly lower
  st.SetLabel(label(variant));
  cholmod_free_factor(&L, &cm.c);
}

// One solve, its workspace reused; its answer checked against clothsim's (both exact).
void BM_IeSolve_Cholmod(benchmark::State& st) {
  auto s = sheet(static_cast<int>(st.range(0)));
  const int variant = static_cast<int>(st.range(1));
  Cholmod cm(variant);
  cholmod_sparse a = bench::cholmod_view(s->lower);
  cholmod_factor* L = cholmod_analyze(&a, &cm.c);
  cholmod_factorize(&a, L, &cm.c);
  const std::size_t n = static_cast<std::size_t>(s->lower.rows());
  cholmod_dense* b = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &cm.c);
  Eigen::Map<Eigen::VectorXd>(static_cast<double*>(b->x), static_cast<Eigen::Index>(n)) =
      Eigen::Map<const Eigen::VectorXd>(s->r.data(), static_cast<Eigen::Index>(n));
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
  for (auto _ : st) {
    cholmod_solve2(CHOLMOD_A, L, b, nullptr, &x, nullptr, &y, &e, &cm.c);
    benchmark::DoNotOptimize(x->x);
  }
  CholeskyPreconditioner f;
  f.analyse(s->A);
  f.factorize(s->A, VelocityFilter{});
  Eigen::Matrix3Xd z;
  f.apply(s->r, z);
  const Eigen::Map<const Eigen::VectorXd> ours(z.data(), static_cast<Eigen::Index>(n));
  const Eigen::Map<const Eigen::VectorXd> theirs(static_cast<double*>(x->x), static_cast<Eigen::Index>(n));
  const double gap = (ours - theirs).cwiseAbs().maxCoeff() / ours.cwiseAbs().maxCoeff();
  st.counters["relative_gap"] = gap;
  if (!(gap < 1e-9)) st.SkipWithError("CHOLMOD's solve differs from clothsim's");
  st.SetLabel(label(variant));
  cholmod_free_dense(&x, &cm.c);
  cholmod_free_dense(&y, &cm.c);
  cholmod_free_dense(&e, &cm.c);
  cholmod_free_dense(&b, &cm.c);
  cholmod_free_factor(&L, &cm.c);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int n : {32, 64, 128, 256}) b->Arg(n);
}
void variants(benchmark::internal::Benchmark* b) {
  for (int n : {32, 64, 128, 256})
    for (int v = 0; v < 4; ++v) b->Args({n, v});
}

}  // namespace

BENCHMARK(BM_IeJacobiIteration_Clothsim)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IeAnalyse_Clothsim)->Apply(sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IeAnalyse_Cholmod)->Apply(variants)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IeFactorize_Clothsim)->Apply(sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IeFactorize_Cholmod)->Apply(variants)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IeSolve_Clothsim)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IeSolve_Cholmod)->Apply(variants)->Unit(benchmark::kMicrosecond);
