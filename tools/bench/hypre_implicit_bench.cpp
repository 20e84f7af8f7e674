// hypre's BoomerAMG beside clothsim's preconditioners on implicit Euler's step Hessian
// (issue #37: docs/notes/2026-11-28-backward-euler-at-scale.md, "Round s35"):
//   build/tools/bench/hypre_implicit_benchmarks [--sides 32,64,128,256] [--repeats 3] [--steps K] [--exact]
//                                               [--only TEXT: the BoomerAMG configurations so named]
// Built only where CMake finds hypre and MPI (libhypre-dev); a plain executable, no mpirun:
// MPI starts as a singleton and every hypre object lives on MPI_COMM_SELF.
//
// The matrix: the refined drape's projected step Hessian at its initial state, the one the
// CHOLMOD peer factors (implicit_sheet.h), or the same after K implicit Euler steps (--steps 6:
// the sheet buckled over the ball at 0.1 s); --exact takes Phi's exact Hessian as CG's matrix,
// the preconditioners still built from the projected one, as inside Newton (hypre's own PCG,
// which would solve the projected one, is then left out). One right-hand
// side, solved from zero to the relative residuals Newton asks for at a step's first solve and
// near its end (1e-2 and 1e-6), by
//  - clothsim's PCG with block Jacobi, and with its V-cycle (multigrid_preconditioner.h);
//  - hypre's PCG with BoomerAMG (one V-cycle per iteration) for each configuration below;
//  - clothsim's PCG with the same BoomerAMG V-cycle as its preconditioner.
// Per row: the setup (block Jacobi: the diagonal's inverses; the V-cycle: its Galerkin
// operators, the analysis once per model apart; BoomerAMG: its whole setup), iterations and
// solve time per tolerance; times are this thread's CPU, the least of --repeats runs. Every
// answer's true residual |b - A x| / |b| is recomputed with clothsim's mat-vec and printed.
// What it measured kept BoomerAMG out of the core: a setup that a Newton step's few solves per
// held set cannot amortise, and iterations that grow on the buckled sheet (BENCHMARKS.md).
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <mpi.h>

#include <Eigen/Geometry>  // cross, for the rotations
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/linear/conjugate_gradient.h"
#include "core/linear/multigrid_preconditioner.h"
#include "implicit_sheet.h"
#include "least_cpu.h"

using namespace clothsim;

namespace {

// The least CPU time of `repeats` calls of f (ms).
template <class F>
double least_ms(int repeats, F&& f) {
  return 1e3 * bench::least_cpu_seconds(repeats, f);
}

// A BoomerAMG configuration (hypre's reference manual, "ParCSR Solvers: BoomerAMG").
struct AmgConfig {
  const char* name;
  int functions;       // 1: scalar AMG; 3: systems AMG, x y z interleaved as clothsim stores them
  int nodal;           // 0: unknown-based coarsening; 4: nodal, a block's row-sum norm (MFEM's choice)
  int coarsen;         // 10 HMIS, 8 PMIS
  double theta;        // strong threshold
  int agg_levels;      // levels of aggressive coarsening (multipass interpolation there)
  int relax;           // 13/14 l1-Gauss-Seidel forward down, backward up (symmetric); 8 l1 symmetric GS; 16 Chebyshev
  int sweeps;
  bool rotations = false;  // the sheet's three rotations as interpolation vectors (GM approach 2),
                           // the elasticity setup (Baker, Kolev & Yang 2010), so P keeps rigid modes
};

const AmgConfig kConfigs[] = {
    {"scalar HMIS ext+i l1GS th0.25", 1, 0, 10, 0.25, 0, 13, 1},
    {"sys3 HMIS ext+i l1GS th0.25", 3, 0, 10, 0.25, 0, 13, 1},
    {"sys3 HMIS ext+i l1GS th0.5", 3, 0, 10, 0.5, 0, 13, 1},
    {"sys3 HMIS ext+i l1GS th0.9", 3, 0, 10, 0.9, 0, 13, 1},
    {"sys3 nodal HMIS ext+i l1GS th0.5", 3, 4, 10, 0.5, 0, 13, 1},
    {"sys3 nodal PMIS ext+i l1GS th0.5", 3, 4, 8, 0.5, 0, 13, 1},
    {"sys3 nodal HMIS agg1 l1GS th0.5", 3, 4, 10, 0.5, 1, 13, 1},
    {"sys3 nodal HMIS ext+i l1GS x2 th0.5", 3, 4, 10, 0.5, 0, 13, 2},
    {"sys3 nodal HMIS ext+i Cheb th0.5", 3, 4, 10, 0.5, 0, 16, 1},
    {"sys3 HMIS ext+i l1GS x2 th0.5", 3, 0, 10, 0.5, 0, 13, 2},
    {"sys3 nodal HMIS ext+i l1GS th0.5 + rotations", 3, 4, 10, 0.5, 0, 13, 1, true},
};

// A as hypre's IJ/ParCSR matrix and two vectors on one rank.
struct HypreSystem {
  HYPRE_IJMatrix ij = nullptr;
  HYPRE_ParCSRMatrix A = nullptr;
  HYPRE_IJVector ib = nullptr, ix = nullptr;
  HYPRE_ParVector b = nullptr, x = nullptr;
  std::vector<HYPRE_BigInt> rows;  // 0 .. n - 1, for the vectors' gets and sets
  HypreSystem(const Eigen::SparseMatrix<double, Eigen::RowMajor>& m) {
    const HYPRE_BigInt n = m.rows();
    HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, n - 1, 0, n - 1, &ij);
    HYPRE_IJMatrixSetObjectType(ij, HYPRE_PARCSR);
    std::vector<HYPRE_Int> sizes(static_cast<std::size_t>(n));
    for (HYPRE_BigInt i = 0; i < n; ++i) sizes[i] = m.outerIndexPtr()[i + 1] - m.outerIndexPtr()[i];
    HYPRE_IJMatrixSetRowSizes(ij, sizes.data());
    HYPRE_IJMatrixInitialize(ij);
    std::vector<HYPRE_BigInt> cols(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
    rows.resize(static_cast<std::size_t>(n));
    for (HYPRE_BigInt i = 0; i < n; ++i) rows[i] = i;
    HYPRE_IJMatrixSetValues(ij, static_cast<HYPRE_Int>(n), sizes.data(), rows.data(), cols.data(), m.valuePtr());
    HYPRE_IJMatrixAssemble(ij);
    HYPRE_IJMatrixGetObject(ij, reinterpret_cast<void**>(&A));
    for (HYPRE_IJVector* v : {&ib, &ix}) {
      HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, n - 1, v);
      HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR);
      HYPRE_IJVectorInitialize(*v);
      HYPRE_IJVectorAssemble(*v);
    }
    HYPRE_IJVectorGetObject(ib, reinterpret_cast<void**>(&b));
    HYPRE_IJVectorGetObject(ix, reinterpret_cast<void**>(&x));
  }
  ~HypreSystem() {
    HYPRE_IJVectorDestroy(ix);
    HYPRE_IJVectorDestroy(ib);
    HYPRE_IJMatrixDestroy(ij);
  }
  HypreSystem(const HypreSystem&) = delete;
  HypreSystem& operator=(const HypreSystem&) = delete;
  int size() const { return static_cast<int>(rows.size()); }
  void set(HYPRE_IJVector v, const Eigen::Matrix3Xd& from) const {
    HYPRE_IJVectorSetValues(v, size(), rows.data(), from.data());
  }
  void get(HYPRE_IJVector v, Eigen::Matrix3Xd& to) const {
    to.resize(3, size() / 3);
    HYPRE_IJVectorGetValues(v, size(), rows.data(), to.data());
  }
};

// The rotations about the sheet's centre, e_k x (x_i - c) at each body i: with the nodal
// coarsening's translations, the rigid modes a coarse space for a sheet should reproduce.
struct Rotations {
  HYPRE_IJVector ij[3] = {nullptr, nullptr, nullptr};
  HYPRE_ParVector v[3] = {nullptr, nullptr, nullptr};
  Rotations(const HypreSystem& h, const Eigen::Matrix3Xd& x) {
    const Vec3 c = x.rowwise().mean();
    const int n = h.size();
    for (int k = 0; k < 3; ++k) {
      Eigen::Matrix3Xd mode = Eigen::Matrix3Xd::Zero(3, n / 3);  // bodies past the particles: 0
      for (Eigen::Index i = 0; i < std::min<Eigen::Index>(x.cols(), n / 3); ++i)
        mode.col(i) = Vec3::Unit(k).cross(Vec3(x.col(i) - c));
      HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, n - 1, &ij[k]);
      HYPRE_IJVectorSetObjectType(ij[k], HYPRE_PARCSR);
      HYPRE_IJVectorInitialize(ij[k]);
      HYPRE_IJVectorSetValues(ij[k], n, h.rows.data(), mode.data());
      HYPRE_IJVectorAssemble(ij[k]);
      HYPRE_IJVectorGetObject(ij[k], reinterpret_cast<void**>(&v[k]));
    }
  }
  ~Rotations() {
    for (HYPRE_IJVector& w : ij) HYPRE_IJVectorDestroy(w);
  }
  Rotations(const Rotations&) = delete;
  Rotations& operator=(const Rotations&) = delete;
};

// BoomerAMG as a preconditioner: one V-cycle from zero (MaxIter 1, Tol 0).
HYPRE_Solver make_amg(const AmgConfig& c, Rotations* rotations) {
  HYPRE_Solver amg;
  HYPRE_BoomerAMGCreate(&amg);
  HYPRE_BoomerAMGSetPrintLevel(amg, 0);
  HYPRE_BoomerAMGSetMaxIter(amg, 1);
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  HYPRE_BoomerAMGSetNumFunctions(amg, c.functions);
  if (c.nodal) {
    HYPRE_BoomerAMGSetNodal(amg, c.nodal);
    HYPRE_BoomerAMGSetNodalDiag(amg, 1);
  }
  HYPRE_BoomerAMGSetCoarsenType(amg, c.coarsen);
  HYPRE_BoomerAMGSetInterpType(amg, 6);  // extended+i
  HYPRE_BoomerAMGSetPMaxElmts(amg, 4);
  HYPRE_BoomerAMGSetStrongThreshold(amg, c.theta);
  HYPRE_BoomerAMGSetAggNumLevels(amg, c.agg_levels);
  HYPRE_BoomerAMGSetNumSweeps(amg, c.sweeps);
  if (c.relax == 13) {  // forward down, backward up: the cycle stays symmetric, as CG needs
    HYPRE_BoomerAMGSetCycleRelaxType(amg, 13, 1);
    HYPRE_BoomerAMGSetCycleRelaxType(amg, 14, 2);
    HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3);
  } else {
    HYPRE_BoomerAMGSetRelaxType(amg, c.relax);  // the coarsest level: Gaussian elimination
    if (c.relax == 16) HYPRE_BoomerAMGSetChebyOrder(amg, 2);
  }
  if (rotations) {
    HYPRE_BoomerAMGSetInterpVecVariant(amg, 2);
    HYPRE_BoomerAMGSetInterpVecQMax(amg, 4);
    HYPRE_BoomerAMGSetInterpVectors(amg, 3, rotations->v);
  }
  return amg;
}

// hypre's BoomerAMG V-cycle behind clothsim's Preconditioner: z = M^-1 r through the IJ
// vectors (two copies of 3B numbers a cycle).
class HyprePreconditioner : public Preconditioner {
 public:
  HyprePreconditioner(const HypreSystem& s, HYPRE_Solver amg) : s_(s), amg_(amg) {}
  bool ready() const override { return true; }
  void apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const override {
    s_.set(s_.ib, r);
    HYPRE_ParVectorSetConstantValues(s_.x, 0.0);
    HYPRE_BoomerAMGSolve(amg_, s_.A, s_.b, s_.x);
    s_.get(s_.ix, z);
  }

 private:
  const HypreSystem& s_;
  HYPRE_Solver amg_;
};

HYPRE_Int no_setup(HYPRE_Solver, HYPRE_ParCSRMatrix, HYPRE_ParVector, HYPRE_ParVector) { return 0; }

constexpr double kTolerances[2] = {1e-2, 1e-6};

struct Row {
  std::string name;
  double setup_ms = 0.0;
  int iterations[2] = {0, 0};
  double solve_ms[2] = {0.0, 0.0};
  double residual[2] = {0.0, 0.0};  // true |b - A x| / |b|
  bool negative[2] = {false, false};  // CG stopped at negative curvature (an exact, indefinite A)
};

double true_residual(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, const Eigen::Matrix3Xd& x) {
  Eigen::Matrix3Xd ax;
  A.multiply(A, x, ax);
  return (b - ax).norm() / b.norm();
}

void print(int n, const Row& w) {
  std::printf("| %d | %s | %.2f | %d | %.2f | %.2f | %d | %.2f | %.2f | %.1e%s, %.1e%s |\n", n, w.name.c_str(),
              w.setup_ms, w.iterations[0], w.solve_ms[0], w.setup_ms + w.solve_ms[0], w.iterations[1],
              w.solve_ms[1], w.setup_ms + w.solve_ms[1], w.residual[0], w.negative[0] ? " (negative curvature)" : "",
              w.residual[1], w.negative[1] ? " (negative curvature)" : "");
  std::fflush(stdout);
}

// clothsim's PCG on A with `pre` (null: block Jacobi), from zero, to each tolerance.
void clothsim_solves(const bench::ImplicitSheet& s, const Preconditioner* pre, int repeats, Row& w) {
  CgBuffers buffers;
  Eigen::Matrix3Xd x;
  for (int t = 0; t < 2; ++t) {
    CgSettings settings;
    settings.max_iterations = 5000;
    settings.tolerance = kTolerances[t];
    CgResult cg;
    w.solve_ms[t] = least_ms(repeats, [&] { cg = solve_pcg(s.A, s.r, x, settings, buffers, nullptr, pre); });
    w.iterations[t] = cg.iterations;
    w.residual[t] = true_residual(s.A, s.r, x);
    w.negative[t] = cg.negative_curvature;
  }
}

void clothsim_rows(int n, const bench::ImplicitSheet& s, SpringBlockMatrix& projected, int repeats) {
  Row jacobi{"clothsim block Jacobi"};
  jacobi.setup_ms = least_ms(repeats, [&] { invert_diagonal(projected); });
  clothsim_solves(s, nullptr, repeats, jacobi);
  print(n, jacobi);

  Row vcycle{"clothsim V-cycle (Chebyshev fine)"};
  MultigridPreconditioner mg;
  mg.analyse(projected, s.model.grid_nx, s.model.grid_ny);  // once per model: not in the setup
  vcycle.setup_ms = least_ms(repeats, [&] {
    if (!mg.build(projected, VelocityFilter{}, s.state.inv_mass)) std::exit(2);
  });
  clothsim_solves(s, &mg, repeats, vcycle);
  std::fprintf(stderr, "  V-cycle: %d levels\n", mg.levels());
  print(n, vcycle);
}

// hypre's PCG (2-norm of the residual against |b|) with BoomerAMG set up apart.
void hypre_rows(int n, const bench::ImplicitSheet& s, HypreSystem& h, const AmgConfig& c, int repeats,
                bool own_pcg) {
  std::unique_ptr<Rotations> rotations;
  if (c.rotations) rotations = std::make_unique<Rotations>(h, s.state.x);
  HYPRE_Solver amg = make_amg(c, rotations.get());
  h.set(h.ib, s.r);
  Row own{std::string("hypre PCG + ") + c.name};
  own.setup_ms = least_ms(repeats, [&] { HYPRE_BoomerAMGSetup(amg, h.A, h.b, h.x); });
  Eigen::Matrix3Xd x;
  for (int t = 0; t < 2 && own_pcg; ++t) {
    HYPRE_Solver pcg;
    HYPRE_ParCSRPCGCreate(MPI_COMM_SELF, &pcg);
    HYPRE_PCGSetTwoNorm(pcg, 1);
    HYPRE_PCGSetTol(pcg, kTolerances[t]);
    HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
    HYPRE_PCGSetMaxIter(pcg, 5000);
    HYPRE_ParCSRPCGSetPrecond(pcg, HYPRE_BoomerAMGSolve, no_setup, amg);
    HYPRE_ParCSRPCGSetup(pcg, h.A, h.b, h.x);
    own.solve_ms[t] = least_ms(repeats, [&] {
      HYPRE_ParVectorSetConstantValues(h.x, 0.0);
      HYPRE_ParCSRPCGSolve(pcg, h.A, h.b, h.x);
    });
    HYPRE_Int it = 0;
    HYPRE_PCGGetNumIterations(pcg, &it);
    own.iterations[t] = it;
    h.get(h.ix, x);
    own.residual[t] = true_residual(s.A, s.r, x);
    HYPRE_ParCSRPCGDestroy(pcg);
  }
  if (own_pcg) print(n, own);

  Row inside = own;  // the same setup, the cycle inside clothsim's PCG
  inside.name = std::string("clothsim PCG + ") + c.name;
  HyprePreconditioner pre(h, amg);
  clothsim_solves(s, &pre, repeats, inside);
  print(n, inside);
  HYPRE_BoomerAMGDestroy(amg);
}

std::vector<int> parse_sides(const char* text) {
  std::vector<int> sides;
  for (const char* p = text; *p;) {
    char* end = nullptr;
    const long v = std::strtol(p, &end, 10);
    if (end == p || v < 2 || v > 4096) {
      std::fprintf(stderr, "hypre_implicit_benchmarks: --sides: not a list of sides from 2 to 4096: %s\n", text);
      std::exit(2);
    }
    sides.push_back(static_cast<int>(v));
    p = *end == ',' ? end + 1 : end;
  }
  return sides;
}

// A whole number from min to 100000 for `flag`, or one line naming it and exit 2.
int parse_count(const char* flag, const char* text, int min) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end || v < min || v > 100000) {
    std::fprintf(stderr, "hypre_implicit_benchmarks: %s: not a whole number from %d: %s\n", flag, min, text);
    std::exit(2);
  }
  return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sides = {32, 64, 128, 256};
  int repeats = 3;
  bool exact = false;
  int steps = 0;
  const char* only = "";  // hypre's configurations whose name contains this
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--sides") && i + 1 < argc) {
      sides = parse_sides(argv[++i]);
    } else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) {
      repeats = parse_count("--repeats", argv[++i], 1);
    } else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
      steps = parse_count("--steps", argv[++i], 0);
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--exact")) {
      exact = true;
    } else {
      std::fprintf(stderr, "hypre_implicit_benchmarks: unknown argument %s (--sides LIST, --repeats N, --steps K, --exact, --only TEXT)\n",
                   argv[i]);
      return 2;
    }
  }
  MPI_Init(&argc, &argv);
  HYPRE_Init();
  std::printf("| side | preconditioner | setup ms | iterations to 1e-2 | solve ms | setup + solve ms "
              "| iterations to 1e-6 | solve ms | setup + solve ms | true residuals |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (int n : sides) {
    auto s = bench::implicit_sheet(n, exact ? HessianBlocks::Exact : HessianBlocks::Projected, steps);
    SpringBlockMatrix projected = s->A;
    projected.use_projected();
    // hypre and the preconditioners see the projected matrix; CG's matrix is s->A.
    HypreSystem h(bench::scalar_matrix<Eigen::RowMajor>(s->A, bench::Triangle::Both, true));
    clothsim_rows(n, *s, projected, repeats);
    for (const AmgConfig& c : kConfigs)
      if (std::strstr(c.name, only)) hypre_rows(n, *s, h, c, repeats, !exact);
  }
  HYPRE_Finalize();
  MPI_Finalize();
  return 0;
}
