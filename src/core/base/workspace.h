// Scratch space owned by one run, so steps allocate nothing. Integrators size what they use.
// Nothing in it carries from one step to the next but sizes and patterns (what does, the
// implicit warm start, lives in State). The caches are declared here and defined on the floors
// that fill them (implicit/implicit_cache.h, solvers/solver_cache.h), so this header, on the
// ground floor, needs neither.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>

namespace clothsim {

struct SolverCache;  // xpbd's, projective_dynamics' and vbd's scratch (solvers/solver_cache.h)
struct SolverCacheDeleter {
  void operator()(SolverCache* cache) const;
};

struct ImplicitCache;  // the implicit solver's sparse pattern and buffers (implicit/implicit_cache.h)
struct ImplicitCacheDeleter {
  void operator()(ImplicitCache* cache) const;
};

struct Workspace {
  Eigen::Matrix3Xd a, x1, v1, a1, x2, v2, a2, a3;  // (3 x B) scratch
  std::unique_ptr<ImplicitCache, ImplicitCacheDeleter> implicit;
  std::unique_ptr<SolverCache, SolverCacheDeleter> solvers;
  // Receives implicit_euler's Newton trace, one line per event (docs/implicit_euler.md, "The
  // Newton trace"); empty: no trace. The tool sets it; the engine reads no environment.
  std::function<void(const char* line)> newton_trace;
  // Told after each iteration of xpbd, projective_dynamics and vbd its number (from 1) and the
  // end-of-step positions it reached (3 x B), before the step ends there; empty: not called.
  // The convergence study (study/convergence.h) records every iteration of one step with it.
  std::function<void(int iteration, const Eigen::Matrix3Xd& y)> on_iteration;
  // Polled after every iteration of an iterative step (xpbd, projective_dynamics, vbd, Newton):
  // true ends the step there, short of its iterations, so a run stops within one iteration of
  // being asked however many a step takes (Run::set_stop_check sets it; empty: never).
  std::function<bool()> interrupt;
  bool interrupted() const { return interrupt && interrupt(); }
};

}  // namespace clothsim
