// Vertex block descent (Chen, Kirchhoff, Li, Chen, Macklin, Tanaka 2024, "Vertex Block
// Descent"): Gauss-Seidel over the vertices, each moved by one 3x3 Newton step on the step's G
// (step_problem.h) with every other vertex held, colour by colour so that no two vertices of
// a colour share a spring (the order a parallel sweep would take; here it runs on one core).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "step_problem.h"

namespace clothsim {

// The springs at each vertex and a greedy colouring, built once per model.
struct VbdGraph {
  std::vector<std::int32_t> start;   // (B + 1) CSR offsets into `spring`
  std::vector<std::int32_t> spring;  // spring indices incident to each body
  std::vector<std::int32_t> neighbour;  // the other end of each of those springs
  std::vector<std::vector<std::int32_t>> colours;  // bodies by colour, ascending
  const Model* model = nullptr;
  std::size_t springs = 0;
};

void build_vbd_graph(const Model& model, VbdGraph& g);

// The paper's adaptive first guess y = x + h v + h^2 a~, with a~ the acceleration a's
// component along gravity clamped to [0, |g|] (full gravity for a falling vertex, none for one
// that rests). The paper measures a as (v_n - v_{n-1}) / h; a State keeps no previous
// velocity, so a is the force evaluation at the step's start (a step stays a function of the
// State alone).
void vbd_initial_guess(const Model& model, const StepProblem& p, const State& state,
                       const Eigen::Matrix3Xd& acceleration, Eigen::Matrix3Xd& y);

// A vertex's contact within a step: implicit_euler's held plane (step_problem.h), taken when
// the vertex first enters a collider's reach, and whether its last step was held on it.
struct VbdContact {
  Vec3 normal = Vec3::UnitY();
  double plane = 0.0;
  std::uint8_t planed = 0, held = 0;
};

// Contacts as hard constraints (in place of the paper's penalty, so that converged VBD is
// converged implicit_euler): after a vertex's Newton step to y, a vertex inside a collider's
// reach or held at its last step keeps n . y >= plane; below it, y moves to its local
// quadratic's minimiser on the plane, y += mu H^-1 n with mu = (plane - n . y) / (n . H^-1 n).
// H: the vertex's Hessian as xx, yy, zz, xy, xz, yz.
void vbd_hold(const Colliders& colliders, const Vec3& from, const double H[6], Vec3& y, VbdContact& c);

// The barrier contact model in VBD (collision.model: barrier), as Chen et al. 2024 take IPC's
// barrier: each vertex's 3x3 Newton system gains its pairs' barrier and lagged friction
// (contact/barrier_contacts.h, step_pair_terms: gradient, Hessian projected to PSD), and its
// step is filtered so that every pair keeps at least a tenth of its distance (the closed-form
// bounds of barrier_kernels.h, the paper's conservative step bound): no distance reaches zero.
struct VbdBarrier {
  const Model* model = nullptr;
  const Eigen::Matrix3Xd* start_x = nullptr;  // (3 x B) x_n, where friction is lagged
  const Eigen::VectorXd* inv_mass = nullptr;  // (B)
  double h = 0.0;
};
constexpr double kVbdBarrierKeep = 0.1;

// One sweep: every movable vertex from first_body on, colour by colour, takes its 3x3 Newton
// step; `contacts` (B) holds their contacts through the step (held planes; unused with a
// barrier, which replaces them).
void vbd_sweep(const StepProblem& p, const VbdGraph& g, Eigen::Matrix3Xd& y, std::vector<VbdContact>& contacts,
               int first_body = 0, const VbdBarrier* barrier = nullptr);

}  // namespace clothsim
