// converge's plan, as the CLI and the Python module both make it: the options and their
// defaults (one step of 1/60 s from 5 states, 1..50 iterations of the four iterative methods)
// and the study they ask for. tools/cli/studies/cmd_converge.cpp parses and prints. Every
// function throws UsageError with a one-line message naming the option.
#pragma once

#include <string>
#include <vector>

#include "clip/common/scene_options.h"
#include "core/integrators/integrator_kind.h"
#include "study/convergence.h"

namespace clothsim::clip {

struct ConvergeOptions {
  SceneOptions scene;
  std::string dt = "1/60";
  std::string integrators = "xpbd,projective_dynamics,vbd,implicit_euler";
  std::string states = "5", max_iterations = "50";
  std::string csv, plot, summary;
  std::string shard;  // --shard K/N|auto (study_shard.h)
};

// --integrators: the iterative methods by name: xpbd, projective_dynamics, vbd, implicit_euler and the
// implicit family (implicit_midpoint, newmark, generalized_alpha, bdf2), each against its own step.
std::vector<IntegratorKind> parse_methods(const std::string& text);

// The study the options ask for: the step, the states, the iterations and the methods.
ConvergenceSpec plan_converge(const ConvergeOptions& o);

}  // namespace clothsim::clip
