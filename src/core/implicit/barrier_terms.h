// The barrier contact model inside implicit_euler's solve (collision.model: barrier): its
// terms of Phi, its Newton blocks, the line search's bound and a feasible start.
//
// With the barrier, Phi(dv) (step_potential.h) gains sum_pairs [b(d(y)) + D(y)], y the
// end-of-step positions x_n + h (v_n + dv): the barrier at the end of the step and IPC's lagged
// friction (contact/barrier_contacts.h, step_pair_terms). Their gradient with respect to dv is
// h times that with respect to y, their Hessian h^2 times, projected to PSD per pair (Li et
// al. 2020). A pair's Hessian also has cross blocks between a particle and a dynamic sphere;
// the block pattern holds none (sparse_system.h: one block per body and per spring), so they
// are left out: [K -K; -K K] becomes diag(K, K), still PSD, so every direction still descends
// and the line search on the true Phi converges (more slowly near a dynamic sphere).
// Phi is +inf where a distance is <= 0; the line search starts at the largest step that keeps
// every distance above a tenth of its value (closed form, barrier_kernels.h), so no iterate
// ever reaches zero, and the solve starts from a guess with every particle outside.
#pragma once

#include <Eigen/Core>

#include "sparse_system.h"
#include "step_potential.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

// How much of its distance a line-search trial may take from a pair: it keeps at least this
// fraction (IPC's CCD keeps 0.1-0.2 of the time of impact in hand the same way).
constexpr double kBarrierKeep = 0.1;

// Phi's barrier terms at end positions y: their energy into value (phi and magnitude), h times
// their y-gradient into gradient (3 x B; immovable bodies are zeroed by the caller). The
// friction's displacement is y - start.x over form.damper_h, lagged at form.lag_x (step_form.h).
void add_barrier_potential(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                           Eigen::Matrix3Xd& gradient, PotentialValue& value);

// A's diagonal blocks (exact and projected alike) += h^2 times each pair's projected Hessian at y,
// on movable bodies; the SIMD copy of the diagonal is refreshed.
void add_barrier_hessian(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                         SpringBlockMatrix& A);

// The largest line-search step along dv's direction d from end positions y (which move by h d):
// every distance keeps kBarrierKeep of itself. 1 when no pair closes.
double barrier_line_bound(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                          const Eigen::Matrix3Xd& d);

// Makes the first guess feasible: a particle whose end position x_n + h (v_n + dv) (mapped to
// the barrier's point, StepForm::contact_stage) lies at or inside a collider has its dv changed
// so that it ends d-hat / 2 outside. Returns how many.
int barrier_feasible_start(const Model& model, const State& start, const StepForm& form, Eigen::Matrix3Xd& dv);

}  // namespace clothsim
