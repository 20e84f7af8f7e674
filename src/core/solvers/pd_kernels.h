// Projective dynamics' two halves (Liu, Bargteil, O'Brien and Kavan 2013, "Fast Simulation of
// Mass-Spring Systems") over the step's G (step_problem.h), each spring a term
// k/2 |y_a - y_b - p_s|^2 with |p_s| its blended rest length:
//     local:  p_s = rest_s (y_a - y_b) / |y_a - y_b|;
//     global: (A + L) y = A yhat + J p, with A = diag(a_i), L the springs' Laplacian
//             (weights k_s), J p the springs' projections scattered to their ends;
// Contacts are forces lambda_i n_i in the right-hand side, one multiplier per particle
// raised by the depth the last solve left it below its plane (Uzawa's iteration on the
// one-sided constraint n_i . y_i >= plane_i, step a_i = m_i/h^2 + c/h, clamped at 0; the
// matrix's full diagonal overshoots where contacts share springs), so the matrix stays
// constant and, converged, the contact is held exactly: not Bouaziz et al. 2014's weighted
// terms, which change the matrix with every contact set and, stiff, freeze the particles
// they hold. The plane is implicit_euler's held plane (step_contacts.h: normal from the
// collider's end-of-step centre to the particle's start, at reach + clearance), taken when
// the particle first enters a collider's reach in the step, so converged PD is converged
// implicit_euler with contacts too. The matrix is the
// same for x, y and z, so one scalar LDL^T factor (Liu et al.'s prefactored Cholesky) serves
// the three columns, solved together in one SIMD sweep over the factor's supernodes each way
// (pd_solve_kernels.h); it depends only
// on h and the pins, so it is factored when one of them changes and reused otherwise.
//
// The global solve runs in defect-correction form, y <- y + (L D L^T)^-1 (b(y) - (A + L) y):
// the residual in double (each spring's k (p_s - d_s), no sum of large opposite terms), the
// factor's panels in float (half the bytes the solve streams). Its fixed point is the exact
// one's, (A + L) y = b(y); the float factor only perturbs each correction by about float's
// epsilon times the matrix's condition, which shrinks with the residual.
//
// The local step runs by the grid's stencil families in SIMD (pd_local_kernels.h) when the
// model's spring layout covers every spring, else as a scalar pass over the spring list.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <cstdint>
#include <vector>

#include "pd_supernodes.h"
#include "step_problem.h"

namespace clothsim {

struct PdFactor {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  SupernodesF panels;                    // the factor's L and D by supernodes in float, for the solve
  std::vector<std::int32_t> free_index;  // (B) row of a movable body, -1 where immovable
  std::vector<std::int32_t> row;         // (B) its row in the factor's (permuted) order, or -1
  Eigen::VectorXd inv_mass;              // (B) the pin set it was built for
  double h = 0.0;
  const Model* model = nullptr;
  bool analysed = false;
  int factorizations = 0;                // numeric factorizations so far
};

// One step's right-hand side pieces and scratch, in the factor's row order.
struct PdSystem {
  Eigen::Matrix4Xd z;            // (4 x n) the residual b(y) - (A + L) y, padded as the solve reads it; lane 3 zero
  Eigen::Matrix<float, 4, Eigen::Dynamic> dz;  // (4 x n) z in float, then the correction the solve makes of it
  std::vector<double> rest;      // (slots) blended rest lengths by the layout's slot order
  std::vector<std::int32_t> pushed;  // particles whose contact multiplier is positive, ascending
  std::vector<std::int32_t> inside, visit;  // scratch: particles in a collider's reach; the union
  std::vector<std::uint8_t> planed;  // (P) 1 once a particle has taken its contact plane this step
  std::vector<Vec3> normal;          // (P) that plane's normal
  std::vector<double> plane;         // (P) n . y on it, m
};

// Refactors when h or the pins differ from the factor's. Returns whether it did.
bool pd_prepare_factor(const Model& model, const StepProblem& p, const Eigen::VectorXd& inv_mass,
                       PdFactor& f);

// The step's scratch, its contact planes cleared and, with a layout, the rest lengths by slot.
void pd_prepare_step(const Model& model, const StepProblem& p, const PdFactor& f, PdSystem& s);

// One local-global iteration: y <- the global solve with the projections taken at y and the
// contact forces lambda (P, N; zeros at the step's start), then lambda updated at the new y.
// Immovable particles' y must hold their targets (the springs to them read y).
void pd_iteration(const Model& model, const StepProblem& p, const PdFactor& f, Eigen::Matrix3Xd& y,
                  PdSystem& s, std::vector<double>& lambda);

// Wang 2015's Chebyshev weights: omega_1 = 1, omega_2 = 2 / (2 - rho^2),
// omega_{k+1} = 4 / (4 - rho^2 omega_k).
double chebyshev_omega(int k, double rho, double previous);

}  // namespace clothsim
