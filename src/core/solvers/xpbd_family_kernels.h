// XPBD's Gauss-Seidel sweep over the grid's stencil families (spring_layout.h) in SIMD.
//
// Each family splits into two independent sets (no two springs of a set share a particle):
// a row-wise family (i, j) -> (i + di, j) by floor(p / di) mod 2 of its first particle p, any
// other by floor(j / dj) mod 2 of its row. A sweep projects the sets one after another, each
// seeing the updates of the sets before it, which is still Gauss-Seidel (the order the
// paper's parallel colouring and the peers, Houdini's Vellum and Unreal's Chaos, take); within
// a set the projections are independent, so a vector of consecutive positions loads its ends
// contiguously from structure-of-arrays positions and stores back without conflicts. A
// column-wise family's set is walked by its runs of consecutive positions (its rows); a
// row-wise family's set is every other position (di = 1) or every other pair (di = 2), so
// 2L consecutive particles, deinterleaved by lanes or by pairs, are L springs' a and b ends and
// no lane idles. Each constraint's projection is xpbd_kernels.h's formula; the per-spring
// arrays are the family's (rest lengths, gains, multipliers), the set picks its positions.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "step_problem.h"

namespace clothsim {

struct XpbdFamilies {
  // Built once per model:
  const Model* model = nullptr;
  std::size_t springs = 0;
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> runs;  // (2 F) set 2 f + s's [k0, k1)
  std::size_t stride = 0;                 // P padded by a vector
  // (F) the family's rest lengths, zeros past its count: a row-wise set reads 2L positions
  // from any q < count, so every per-position array is padded by 2 kSpringLanePad (the
  // layout's own padding stops at a multiple of kSpringLanePad, which a tail overran).
  std::vector<std::vector<double>> rest;
  // Per step size and pin set:
  std::vector<double> w;                  // (stride) inverse masses, 0 past P
  std::vector<std::vector<double>> gain;  // (F) 1 / the projection's denominator by position, 0: none
  double h = 0.0;
  // Per step, structure of arrays (component c of particle i at c stride + i):
  std::vector<double> y;                  // (3 stride) the iterate
  std::vector<double> x;                  // (3 stride) the step's start positions
  std::vector<std::int32_t> touching;      // particles inside a collider's reach
  std::vector<std::vector<double>> lambda;  // (F) multipliers by position
};

// Readies the sets (once per model) and loads the step: y (3 x B), the start positions and
// the inverse masses.
void xpbd_load_families(const Model& model, const StepProblem& p, const Eigen::VectorXd& inv_mass,
                        const Eigen::Matrix3Xd& y, XpbdFamilies& f);

// One Gauss-Seidel sweep over every family's two sets.
void xpbd_family_sweep(const Model& model, double h, XpbdFamilies& f);

// Every movable particle inside a collider's reach projected out (xpbd_kernels.h).
void xpbd_family_contacts(const Model& model, const StepProblem& p, XpbdFamilies& f);

// The particles' iterate back into y (3 x B).
void xpbd_store_families(const XpbdFamilies& f, int particles, Eigen::Matrix3Xd& y);

}  // namespace clothsim
