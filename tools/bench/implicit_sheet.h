// What the peer benchmarks of implicit Euler's linear solve share (cholmod_implicit_bench.cpp,
// hypre_implicit_bench.cpp): the refined drape's step Hessian, captured once per side, and
// its scalar form for a library that reads compressed rows or columns.
//
// The sheet: scenes/drape.yaml at N x N particles, the same 4 m sheet and 1024 kg at every
// side (particle mass (32/N)^2 kg, `bench --scale`'s rule with 32 first), h = 1/60 s, at its
// initial state, or after `steps` implicit Euler steps of 1/60 s (at 0.1 s, 6 steps, the sheet
// lies buckled over the ball: compressed springs, so the exact Hessian is indefinite), the
// Hessian then taken at those positions (Newton's matrix at dv = 0, no contact held). The matrix: M + h^2 K in 3x3 blocks (3B x 3B), projected (SPD, what the
// preconditioners are built from) unless asked for the exact one; pinned bodies and the
// kinematic ball are identity rows.
#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "bench_models.h"
#include "core/implicit/sparse_system.h"
#include "core/implicit/step_potential.h"
#include "core/model/model.h"
#include "core/run/simulation.h"
#include "core/model/state.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::bench {

struct ImplicitSheet {
  Model model;
  State state;
  SpringBlockMatrix A;  // the step Hessian, block Jacobi's inverse formed
  Eigen::Matrix3Xd r;   // (3 x B) a right-hand side: uniform random in [-1, 1], zero where immovable
};

inline std::unique_ptr<ImplicitSheet> implicit_sheet(int n, HessianBlocks blocks = HessianBlocks::Projected,
                                                     int steps = 0) {
  auto s = std::make_unique<ImplicitSheet>();
  const double mass = (32.0 / n) * (32.0 / n);
  s->model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                    {"cloth.particles=[" + std::to_string(n) + "," + std::to_string(n) + "]",
                                     "cloth.particle_mass=" + std::to_string(mass)}));
  s->state = initial_state(s->model);
  Workspace ws;
  for (int k = 0; k < steps; ++k) step(s->model, s->state, method("implicit_euler"), 1.0 / 60.0, ws);
  std::vector<double> length;
  step_lengths(s->model, s->state.x, length);
  build_pattern(s->model, s->A);
  assemble_step_hessian(s->model, s->state.inv_mass, 1.0 / 60.0, length, s->state.x, blocks, s->A);
  const int B = s->A.num_bodies();
  s->r = Eigen::Matrix3Xd::Random(3, B);
  // The Newton system's right-hand side is zero on immovable bodies (sparse_system.h).
  for (int i = 0; i < B; ++i)
    if (s->state.inv_mass[i] == 0.0) s->r.col(i).setZero();
  return s;
}

// A's blocks as scalar triplets (3B x 3B), both triangles or the lower one only; `projected`
// takes the projected blocks whatever A holds (the matrix the preconditioners are built from).
enum class Triangle { Lower, Both };
inline std::vector<Eigen::Triplet<double, int>> scalar_triplets(const SpringBlockMatrix& A, Triangle which,
                                                                bool projected) {
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(9 * (A.num_bodies() + 2 * A.num_springs()));
  auto add = [&t, which](int i, int k, const Mat3& m) {
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        if (which == Triangle::Both || 3 * i + r >= 3 * k + c) t.emplace_back(3 * i + r, 3 * k + c, m(r, c));
  };
  for (int i = 0; i < A.num_bodies(); ++i) add(i, i, projected ? A.diag_projected[i] : A.diag[i]);
  for (std::size_t k = 0; k < A.num_springs(); ++k) {
    const Mat3 g = projected ? A.off_projected(k) : A.off(k);  // symmetric: the same at (a, b) and (b, a)
    add(A.a[k], A.b[k], g);
    add(A.b[k], A.a[k], g);
  }
  return t;
}

// The same as a compressed sparse matrix (column-major for CHOLMOD, row-major for CSR).
template <int Order>
Eigen::SparseMatrix<double, Order> scalar_matrix(const SpringBlockMatrix& A, Triangle which, bool projected) {
  const auto t = scalar_triplets(A, which, projected);
  Eigen::SparseMatrix<double, Order> m(3 * A.num_bodies(), 3 * A.num_bodies());
  m.setFromTriplets(t.begin(), t.end());  // sums a spring's two blocks where they meet twice
  m.makeCompressed();
  return m;
}

}  // namespace clothsim::bench
