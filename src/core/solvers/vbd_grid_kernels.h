// VBD's sweep over a cloth grid in SIMD: the vertices of one colour in vectors, their springs
// read by the grid stencil.
//
// On an nx x ny grid whose springs are all stencil families (spring_layout.h), vertex (i, j)
// takes colour (i mod 3) + 3 (j mod 3): the stencils' steps (1, 0), (2, 0), (0, 1), (0, 2),
// (1, 1), (-1, 1) are never 0 mod 3 in both coordinates, so no spring joins two vertices of a
// colour (nine colours, the grid's regular colouring in place of the greedy one). The
// positions are kept colour-major: colour c's vertices i = ci + 3m, j = cj + 3r at
// (r + 1) RW + m + 1 of c's block, RW = ceil(nx / 3) + 2 (a halo column and row each side).
// The neighbour of a run of colour-c vertices m .. m + L - 1 by a step (di, dj) is then a
// run of colour c' vertices, shifted by floor((ci + di) / 3) columns and floor((cj + dj) / 3)
// rows: contiguous loads, no gathers. Each vertex's 3x3 Newton step is vbd_kernels.h's, and
// so is its contact (vbd_hold, on the few lanes inside a reach or held).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "step_problem.h"
#include "vbd_kernels.h"

namespace clothsim {

struct VbdGrid {
  // Built once per model:
  const Model* model = nullptr;
  std::size_t springs = 0;
  int nx = 0, ny = 0, columns = 0, rows = 0;  // grid; colour subgrid ceil(nx/3) x ceil(ny/3)
  std::size_t row_width = 0, block = 0;        // RW; doubles per colour block (halo, padding)
  std::vector<std::int32_t> index;             // (P) particle -> colour-major index
  std::vector<std::int32_t> particle;          // (9 block) colour-major index -> particle (0 if none)
  struct Step { int family = 0, di = 0, dj = 0; };
  std::vector<Step> steps;                     // (12) each family's step, forwards and back
  std::vector<std::int32_t> spring_at;         // (12 x 9 block) spring along step s, or -1
  // Per step, colour-major (9 blocks):
  std::vector<double> y, target;               // (3 x 9 block)
  std::vector<double> weight;                  // (9 block) a_i, 0 where immovable or no vertex
  std::vector<double> rest;                    // (12 x 9 block) blended rest length, -1: none
  std::vector<double> held;                    // (9 block) 1 where the last step held a vertex
  std::vector<VbdContact> contact;             // (9 block) each vertex's contact (vbd_kernels.h)
  std::vector<double> y_before, y_next;        // (3 x 9 block) the accelerated iterations' y_{k-2}, y_{k-1}
};

// True when VBD's grid sweep applies (every spring in the layout's families, P = nx ny).
bool vbd_by_grid(const Model& model);

// Readies the grid (once per model) and loads the step's problem and first guess y (3 x B).
void vbd_load_grid(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y, VbdGrid& g);

// One sweep over the nine colours (particles only; other bodies are the caller's).
void vbd_grid_sweep(const Model& model, const StepProblem& p, VbdGrid& g);

// Chen et al. 2024's accelerated iterations, after sweep k (from 1) with weight omega:
// y = omega (y - y_{k-2}) + y_{k-2} from k = 2 on, over the free vertices off the colliders
// (an extrapolated vertex on its held plane would cross it); g.y_before and g.y_next carry the
// iterates. vbd_grid_remember(g) before each sweep keeps y_{k-1}.
void vbd_grid_remember(VbdGrid& g, int k);
void vbd_grid_accelerate(VbdGrid& g, int k, double omega);

// The particles' iterate back into y (3 x B).
void vbd_store_grid(const Model& model, const VbdGrid& g, Eigen::Matrix3Xd& y);

}  // namespace clothsim
