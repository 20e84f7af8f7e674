// What one run of a method costs in memory beyond the Model, as its registry row states it
// (IntegratorInfo::memory): the run's own arrays (state, scratch, systems, factors) and the
// final state it keeps for `run --state`. scene/memory_estimate.h adds the Model and asks the
// row; the coefficients come from peak RSS (BENCHMARKS.md, "Memory estimate").
#pragma once

#include "core/base/method_params.h"
#include "core/base/model_params.h"

namespace clothsim {

// A scene's sizes, as the methods' memory terms read them.
struct MemorySizes {
  double particles = 0.0;
  double springs = 0.0;
  double bodies = 0.0;  // particles and sphere bodies
  SolverDefs solvers;   // the iterative solvers' options (VBD's acceleration keeps more)
  PreconditionerKind preconditioner = PreconditionerKind::Auto;  // implicit.preconditioner
};

struct MethodMemory {
  double run = 0.0;          // bytes of the run's own arrays at their peak
  double final_state = 0.0;  // bytes of the State kept to write it
};

// One function per method (or family), named in its registry row.
MethodMemory explicit_family_memory(const MemorySizes& n);
MethodMemory midpoint_memory(const MemorySizes& n);
MethodMemory rk4_memory(const MemorySizes& n);
MethodMemory verlet_memory(const MemorySizes& n);  // velocity_verlet, yoshida4
MethodMemory implicit_euler_memory(const MemorySizes& n);
MethodMemory implicit_family_memory(const MemorySizes& n);  // implicit_midpoint, newmark, generalized_alpha, bdf2
MethodMemory imex_memory(const MemorySizes& n);
MethodMemory xpbd_memory(const MemorySizes& n);
MethodMemory projective_dynamics_memory(const MemorySizes& n);
MethodMemory vbd_memory(const MemorySizes& n);
MethodMemory bs3_memory(const MemorySizes& n);
MethodMemory dopri5_memory(const MemorySizes& n);
MethodMemory rkf78_memory(const MemorySizes& n);

}  // namespace clothsim
