// bench --budget N's plan and files, as the CLI and the Python module both make them: which
// solvers split the budget, the frame rate and T, compare's reference for the scene, each
// split's model (the lane NAME:k through lane_model), the CSV, the plot (tools/plot_budget.py)
// and the compare command that shows the grid's two ends side by side. The study itself is
// study/budget_study.h; tools/cli/studies/cmd_bench.cpp prints its table and verdicts.
//
// The clip of the two ends is a printed compare command, not a built-in --clip: compare already
// runs `xpbd@1/60:30,xpbd@1/1800:1` side by side with error colouring against the same
// reference, and a second renderer of two lanes would be compare again.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "clip/studies/bench_plan.h"
#include "clip/studies/study_common.h"
#include "core/model/model.h"
#include "scene/scene_def.h"
#include "study/budget_study.h"

namespace clothsim::clip {

// The solvers --budget splits when --integrators is not given (those a barrier scene cannot run,
// xpbd and projective_dynamics, are left out with a note on stderr).
inline constexpr const char* kBudgetSolvers = "xpbd,vbd,projective_dynamics,implicit_euler";
// Macklin et al. 2019's frame, for a scene that does not write render.fps.
inline constexpr double kBudgetDefaultFps = 60.0;

struct BudgetPlan {
  std::vector<Lane> lanes;          // per solver, without step or iterations ("xpbd")
  analysis::BudgetSpec spec;        // the reference's step set by fit_budget_reference
  std::string fps_from;             // "--fps", "the scene's render.fps", "the default"
  std::vector<std::string> left_out;  // default solvers the scene cannot run, each with why
};

// --budget N's study: UsageError (one line naming the option) for a budget that is not a whole
// number from 1 to kMaxSolverIterations, beside --dts, --vary, --scale, --shard, --summary,
// --frame-dts or the reference options, a lane that is not an iterative solver or comes with
// @STEP, :N or :tol=, a frame rate out of (0, 1000], and a T that is no whole number of frames.
BudgetPlan plan_budget(const BenchOptions& o, const SceneDef& scene);

// The model every split starts from: `scene` run to T, the runs' memory checked (--max-memory).
Model build_budget_model(const BenchOptions& o, SceneDef& scene, const BudgetPlan& plan);

// compare's reference on `model` (frames/picture_options.h, fit_reference_to_model): RK4 at a
// quarter of the smallest step 1 / (F N), cut to RK4's predicted stable step; on a smooth scene
// the adaptive pair at compare's tolerance. Sets spec.reference_dt and reference_tolerance, and
// spec.solver_settings (the lanes' settings through lane_settings; `plan` must outlive the study).
void fit_budget_reference(BudgetPlan& plan, const Model& model, const SceneDef& scene);

// Per point of `r`, its lane as the grammar spells it: "xpbd@1/1800:1" (compare takes it).
std::vector<std::string> budget_lane_spellings(const BudgetPlan& plan, const analysis::BudgetResult& r);

// The compare command that renders solver i's grid ends side by side (1 x N and N x 1), with the
// user's --set and --duration: "clothsim compare scenes/drape.yaml --integrators
// xpbd@1/60:30,xpbd@1/1800:1 --video budget_xpbd.mp4".
std::string budget_compare_command(const BenchOptions& o, const BudgetPlan& plan, std::size_t solver);

// The plot's title: the scene, N, F and T, and the reference's estimated error.
std::string budget_plot_title(const std::string& name, const analysis::BudgetResult& r);

// --csv (atomically) and the plot (null: none) drawn from it by tools/plot_budget.py; then
// RuntimeFailure when the study was stopped (what stays named) or its reference failed.
void write_budget_outputs(const BenchOptions& o, const std::string& source, const std::string& name,
                          const BudgetPlan& plan, const analysis::BudgetResult& r, const PlotScript* plot);

}  // namespace clothsim::clip
