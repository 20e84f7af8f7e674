// State: everything that changes while a scene runs, as flat arrays (MuJoCo's mjData).
// A State is a value: copy it to checkpoint, compare two to measure error.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "model.h"

namespace clothsim {

// implicit_euler's solver state, kept in State (not in scratch) so that a copied State
// continues bit for bit. B = bodies, P = particles, S = spring slots (slot_count of the
// model's spring layout). Empty arrays mean "no history yet".
struct ImplicitSolverState {
  // The first guess (first_guess.h): the last three steps' velocity changes, and the order of
  // the polynomial through them the next step starts from (0 = dv_n, 1 = the line,
  // 2 = the parabola), chosen by which of them the last solution lay closest to.
  Eigen::Matrix3Xd dv;          // (3 x B) m/s, the last step's v_{n+1} - v_n
  Eigen::Matrix3Xd dv_before;   // (3 x B) m/s, the step before's
  Eigen::Matrix3Xd dv_before2;  // (3 x B) m/s, the one before that
  int guess_order = 0;          // 0, 1 or 2
  std::vector<std::int32_t> held;  // (<= P) particles held on a collider at the last step's end
  // The point the last recorded Newton matrix was assembled at (sparse_system.h). The matrix
  // is scratch and a function of these, so a Workspace that does not hold it rebuilds it.
  struct Linearisation {
    Eigen::Matrix3Xd y;           // (3 x B) m, the iterate's end-of-step positions
    std::vector<double> length;   // (S) m, spring lengths at that step's start
    Eigen::VectorXd inv_mass;     // (B) 1/kg
    double h = 0.0;               // s, the step size; 0 = nothing recorded
    double damper_h = 0.0, drag_h = 0.0;  // s, the rest of its StepForm (implicit/step_form.h)
    std::int64_t assemblies = 0;  // matrices recorded over this State's history (a count)
  } lin;
  // Whether the recorded matrix served when last tried on a new iterate; if not, steps
  // assemble afresh and probe it again only now and then.
  bool lin_trusted = true;
  // Whether the last step's sparse factor (cholesky_preconditioner.h) paid for itself, so that
  // the next builds one at its first solve.
  bool factored = false;
  // A block-Jacobi solve's work when last measured (PCG iterations; 0: never), what a factor
  // carried into later steps must stay cheaper than (newton_solve.h, FactorAccount).
  double jacobi_solve = 0.0;
};

struct State;

// What a method carries from its last step to its next beyond (x, v), and the end state it
// belongs to: a step uses it only while x, v and the inverse masses are still bit for bit
// what that step left, so a projection contact, an event or a write from outside (Python's
// positions) makes the next step start afresh, as a copied State continues exactly.
struct StepHistory {
  // velocity_verlet, yoshida4: the last force pass, a(x_end, v_predicted) (3 x B) m/s^2, and
  // the springs' largest strain at x_end: the next step's first kick (first same as last).
  // newmark, generalized_alpha: the carried (algorithmic) acceleration a_{n+1} (3 x B) m/s^2.
  Eigen::Matrix3Xd a;
  double strain = 0.0;
  // bdf2: the state one step before the end state, its spring lengths by slot (step_lengths),
  // and the step h between them.
  Eigen::Matrix3Xd x_before, v_before;  // (3 x B)
  std::vector<double> length_before;    // (slots) m
  double h = 0.0;                       // s
  // imex: the mark of the damping matrix its last kick assembled at the end state (the
  // Workspace's cache keeps the same mark while it holds that matrix: imex.cpp).
  std::uint64_t matrix_mark = 0;
  IntegratorKind owner = IntegratorKind::ExplicitEuler;  // the method that filled it
  bool filled = false;
  Eigen::Matrix3Xd x, v;      // (3 x B) the end state it belongs to
  Eigen::VectorXd inv_mass;   // (B)
  // Whether `s` is the state the history's step of `kind` left.
  bool continues(IntegratorKind kind, const State& s) const;
  void record(IntegratorKind kind, const State& s);  // after a step of `kind`
};

struct State {
  Eigen::Matrix3Xd x;         // (3 x B) body positions, m (particles, then sphere centres)
  Eigen::Matrix3Xd v;         // (3 x B) body velocities, m/s
  Eigen::VectorXd inv_mass;   // (B) 1/kg; 0 = immovable (pinned particle, kinematic sphere)
  double t = 0.0;             // s
  std::int64_t step = 0;      // steps taken
  std::size_t next_action = 0;  // index into model.timeline of the first action not yet applied
  ImplicitSolverState implicit;  // implicit_euler's warm start and Newton-matrix record
  StepHistory history;           // a method's carried data (the Verlet family, newmark, generalized_alpha, bdf2)
};

// The state at t = 0, with the actions scheduled at t = 0 applied.
State initial_state(const Model& model);

// Applies every timeline action due at or before state.t (pins, unpins, sphere velocities):
// the events phase of a step, and the keyframes at t = 0 of an initial state.
void apply_due_actions(const Model& model, State& state);

}  // namespace clothsim
