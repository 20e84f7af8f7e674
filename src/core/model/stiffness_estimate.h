// How fast a scene's fastest mode is, from its springs and masses alone: the step sizes
// beyond which explicit methods cannot be stable, before running anything.
//
// Linearised about the rest state, the cloth obeys M u'' + D u' + K u = 0 with
//     K = sum_s ks_s (e_a - e_b)(e_a - e_b)^T (x) d_s d_s^T      (3P x 3P, d_s the spring's axis)
// and D the same with kd_s (plus air drag c on the diagonal), over the free particles only
// (a pinned particle's rows and columns are removed). The largest eigenvalue of M^-1 K is
// w_max^2. Two steps bound it:
// 1. (d . w)^2 <= |w|^2, so u^T K u <= u^T (L (x) I3) u for every u, with L the scalar
//    graph Laplacian of the springs (L_ii = sum_{s at i} ks_s, L_ij = -ks_s): the 3-D
//    stiffness is no stiffer than the scalar one, and lambda_max(M^-1 K) <= lambda_max(M^-1 L).
// 2. Gershgorin on the rows of M^-1 L (same eigenvalues as the symmetric M^-1/2 L M^-1/2):
//        w_max^2 <= max_i (sum_{s at i} ks_s + sum_{s at i, other end free} ks_s) / m_i,
//    i.e. 2 sum ks / m for a particle among free neighbours, sum ks / m for a spring to a
//    pin (exact for spring.yaml: k / m = 100, w = 10 rad/s).
// Likewise c_max <= max_i (the same sum over kd_s, + c_air) / m_i for the dampers.
//
// What it predicts, for the modes' own test equation u'' + c u' + w^2 u = 0:
// - undamped (c = 0), symplectic Euler is stable for w h < 2 and RK4 for w h < 2.83, so
//   2 / w_max is the step they cannot exceed by much (a bound on w_max makes it a lower
//   estimate of their limit);
// - damped, the fast root of l^2 + c l + w^2 = 0 is l ~ -c when c > w (overdamped: the
//   dampers are the stiff term). Explicit Euler is stable on the negative real axis for
//   h |l| < 2, so the step it cannot exceed is about 2 / max(w_max, c_max). With the
//   drape's damping 750 N s/m (c_max ~ 1.8e4 /s against w_max ~ 690 rad/s) this, not the
//   springs, sets the explicit methods' limit. Both figures are printed.
// Under collision.model: barrier, each particle's row also holds the barrier's stiffness at
// d-hat / 2 (collision.barrier_stiffness, resolved), a spring to an immovable collider: a
// contact pressed deeper is stiffer still (b'' grows without bound as d -> 0).
// Estimates only: the true stiffness matrix also has a geometric term ks (1 - l0/l) under
// tension, and projection contacts are not linear at all.
#pragma once

#include <vector>

#include "model.h"

namespace clothsim::analysis {

struct StiffnessEstimate {
  double w_max = 0.0;  // rad/s, bound on the fastest undamped frequency (springs)
  double c_max = 0.0;  // 1/s, bound on the fastest damping rate (spring dampers + air drag)
  int particle = -1;   // the particle whose row gives w_max (-1: no free particle with springs)
  // 2 / w_max: the springs-only limit (inf without springs).
  double dt_springs() const;
  // 2 / max(w_max, c_max): the limit with the dampers counted.
  double dt_with_damping() const;
};

// Over the particles free at t = 0 (positive initial inverse mass).
StiffnessEstimate estimate_stiffness(const Model& model);

// The stability limits of the methods (each method's registry row names its own), on the
// scene's fastest mode taken as u'' + c u' + w^2 u = 0 with w = w_max and c = c_max. The two
// bounds come from different Laplacians, but they belong to one mode when every damper is proportional to its spring
// (kd / ks the same on every spring, as in the shipped scenes): D = (kd/ks) K, so that mode's
// rate is (kd/ks) w_max^2 = c_max. Its eigenvalues l = (-c +- sqrt(c^2 - 4 w^2)) / 2; the limit
// is the largest h with both h l inside the method's stability region:
// - explicit_euler, midpoint, rk4: |R(h l)| <= 1, R(z) = sum_{m <= p} z^m / m!, p = 1, 2, 4;
//   undamped (c = 0) explicit Euler and midpoint have no stable step (0), rk4 2.83 / w;
//   overdamped, about 2 / c, 2 / c and 2.785 / c;
// - symplectic_euler: its 2 x 2 step matrix has det 1 - hc and trace 2 - hc - h^2 w^2, stable
//   (Jury) while h^2 w^2 + 2 h c <= 4: h = (sqrt(c^2 + 4 w^2) - c) / w^2 (2 / w undamped);
// - velocity_verlet, yoshida4: the step matrix of their kicks and drift (verlet.h); undamped
//   2 / w and about 1.573 / w;
// - implicit_euler: no limit (infinity) with its Newton solve; with `solver: fixed_point` and
//   K iterations from a forward-Euler predictor, R(z) = sum_{m <= K + 1} z^m (K = 1: 1 + z + z^2,
//   stable undamped for w h <= 1).
// An estimate, like the bounds it is built on: it ignores geometric stiffness and contacts,
// and the Gershgorin bounds make w_max and c_max upper bounds, so real limits are larger
// (about 2.4x on the drape, docs/integrators.md). Infinity without springs or dampers.
//
// R(z)'s coefficients a_m (|R(z)| <= 1 is the region), scanned and bisected as above.
double polynomial_limit(const std::vector<double>& a, double w, double c);
std::vector<double> taylor(int order);  // 1, 1, 1/2, ..., 1/order!: explicit RK of that order
double explicit_limit(int order, double w, double c);  // polynomial_limit(taylor(order), w, c)
double symplectic_euler_limit(double w, double c);
double fixed_point_limit(int iterations, double w, double c);  // R(z) = sum_{m <= K + 1} z^m
// A method given by its 3 x 3 step matrix on (u, u', a) for u'' + c u' + w^2 u = 0 (row
// major, for step h), a the acceleration it carries from one step to the next: the largest h
// with every eigenvalue inside the unit circle, scanned and bisected as polynomial_limit.
// What velocity_verlet and yoshida4 use (verlet.h), whose carried force pass is part of the
// state that must stay bounded.
using StepMatrix = void (*)(double h, double w, double c, double m[9]);
double step_matrix_limit(StepMatrix step, double w, double c);

}  // namespace clothsim::analysis
