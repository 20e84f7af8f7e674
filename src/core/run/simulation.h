// The step, and a run of steps with its bookkeeping.
//
// step() reads as its phases (Box2D's solver stages):
//     integrate (forces inside) -> collisions -> time -> events -> divergence check
// Run wraps a model, a state and a workspace for one integrator, step size and method settings
// (core/base/method_settings.h: the model's defaults with the lane's overrides), advances to
// requested times (output frames), keeps running totals and stops at divergence. Runs of one
// scene share its Model whatever their settings: a lane never copies the model.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "core/model/collisions.h"
#include "core/model/diagnostics.h"
#include "core/model/model.h"
#include "core/model/state.h"
#include "core/integrators/adaptive.h"
#include "core/integrators/integrator.h"

namespace clothsim {

struct StepReport {
  StepStats stats;
  ContactCounts contacts;
};

// One step of size h under `settings` (a run's). Does not check divergence (Run does, at its
// own cadence). Without settings: the model's own (Model::method_defaults()).
StepReport step(const Model& model, const MethodSettings& settings, State& state, IntegratorKind kind, double h,
                Workspace& ws);
StepReport step(const Model& model, State& state, IntegratorKind kind, double h, Workspace& ws);

// Running totals of a run.
struct RunTotals {
  std::int64_t steps = 0;
  std::int64_t force_evals = 0;
  std::int64_t newton_iterations = 0;
  std::int64_t cg_iterations = 0;
  std::int64_t factorizations = 0;      // implicit_euler: sparse Cholesky factors
  std::int64_t assemblies = 0;          // implicit_euler: Newton matrices assembled
  std::int64_t factored_cg_iterations = 0;  // of cg_iterations, preconditioned by a factor
  std::int64_t solver_iterations = 0;   // xpbd, projective_dynamics, vbd: their sweeps,
  double solver_iteration_passes = 0.0; // each weighing this many spring passes (the
                                        // method's registry row; work_units.h)
  std::int64_t projected_steps = 0;     // implicit_euler, the adaptive pairs: steps whose post-step
                                        // projection moved a particle (for a pair, any contact resolved)
  double max_strain = 0.0;              // largest strain a step started from (its first force pass)
  std::int64_t unconverged_steps = 0;   // implicit solves that hit their cap
  double max_residual = 0.0;            // largest final residual of any step
  std::int64_t contact_constraints = 0; // implicit_euler: contacts held inside the solves
  std::int64_t rejected_steps = 0;      // adaptive pairs: trial steps the error control refused
  double last_step = 0.0;               // s, the last step taken (an adaptive pair's varies)
  double smallest_step = 0.0, largest_step = 0.0;  // s, over the accepted steps
  std::int64_t safety_projections = 0;  // implicit_euler: particles the post-step projection
                                        // still had to move (contacts the solve missed)
  double sim_seconds = 0.0;             // wall time spent stepping
  double cpu_seconds = 0.0;             // CPU time of the stepping thread: what the run costs
                                        // with a core to itself, even when runs share cores
  std::optional<Divergence> wrong;      // the first WRONG verdict (diagnostics.h), the run going on
};

// A frame's worth of diagnostics: the row `--metrics` writes.
struct FrameMetrics {
  std::int64_t step = 0;
  double t = 0.0;
  Energies energies;
  double max_strain = 0.0;
  int contacts = 0;              // contacts resolved in the last step
  std::int64_t force_evals = 0;  // cumulative
  std::int64_t newton_iterations = 0;  // cumulative
  std::int64_t cg_iterations = 0;      // cumulative
  double residual = 0.0;         // last step's final implicit residual
  bool converged = true;         // last step's solve converged
  double step_size = 0.0;        // s, the last step's (an adaptive pair's own choice)
  std::int64_t rejected_steps = 0;  // cumulative: an adaptive pair's refused trials
};

// CPU time of the calling thread, s: what runs are charged (RunTotals::cpu_seconds), and what a
// benchmark times a peer library by.
double thread_cpu_seconds();

class Run {
 public:
  // `model` outlives the run; `settings` are the run's own (a lane's: clip::lane_settings),
  // by default the model's.
  Run(const Model& model, IntegratorKind kind, double dt, const MethodSettings& settings);
  Run(const Model& model, IntegratorKind kind, double dt) : Run(model, kind, dt, model.method_defaults()) {}

  // Steps until t >= target (within a small tolerance of dt). Returns false once diverged;
  // divergence() then says at which step and time, and why. Returns true but short of the
  // target when the stop check fired (stopped()): callers that stop on a signal check it.
  bool advance_to(double target);
  // Polled before every step of advance_to, and after every iteration of an iterative step, so a
  // run at any step size and any iteration count stops within one iteration of being asked (a relaxed atomic load behind a std::function costs a few ns, nothing
  // beside a step). Once it has returned true the run is stopped for good: advance_to no
  // longer steps. Set it before advancing; the engine itself knows nothing of signals.
  void set_stop_check(std::function<bool()> stop) {
    stop_ = std::move(stop);
    ws_.interrupt = stop_;  // inside a step's iterations too (Workspace::interrupt)
  }
  bool stopped() const { return stopped_; }
  // Where implicit_euler's Newton trace goes (Workspace::newton_trace); unset: nowhere.
  void set_newton_trace(std::function<void(const char* line)> sink) { ws_.newton_trace = std::move(sink); }
  bool diverged() const { return divergence_.has_value(); }
  const std::optional<Divergence>& divergence() const { return divergence_; }

  const Model& model() const { return model_; }
  const MethodSettings& settings() const { return settings_; }
  // At the last target advanced to. An adaptive pair on a smooth scene steps past its targets
  // (dense output, advance_adaptive): this is then its output there, not the state it steps on.
  const State& state() const { return has_output_ ? output_ : state_; }
  IntegratorKind kind() const { return kind_; }
  double dt() const { return dt_; }
  const RunTotals& totals() const { return totals_; }
  FrameMetrics metrics() const;  // diagnostics of the current state

  // After divergence: the last state that is still finite, at the step divergence names (a
  // state past the strain or energy bound is finite and is that state itself; a non-finite one
  // gives the step before), so a picture of the blow-up shows the cloth as it broke rather
  // than the last output frame. Replayed from the state the diverging advance_to started
  // from with a fresh Workspace: a step is a function of the State alone (a copied State
  // continues bit for bit), so the replay takes exactly the steps the run took. Costs at
  // most the steps of that one advance_to; nothing is kept per step while the run is healthy.
  State last_finite_state() const;

 private:
  const Model& model_;
  IntegratorKind kind_;
  double dt_;
  MethodSettings settings_;  // what every step reads of its method (StepContext::settings)
  State state_;
  State checkpoint_;  // state_ at the start of the current advance_to (last_finite_state replays it)
  Workspace ws_;
  RunTotals totals_;
  StepReport last_;
  std::optional<Divergence> divergence_;
  std::function<bool()> stop_;
  bool stopped_ = false;
  // WRONG's evidence (diagnostics.h): the scene's starting strain, the energy of the current
  // no-work stretch, sampled every energy_every_ steps, and whether work was done since.
  double start_strain_ = 0.0;
  EnergyLedger energy_;
  std::int64_t energy_every_ = 1;
  bool work_since_sample_ = false;
  // An adaptive pair (IntegratorInfo::adaptive): its controller, and the state before its last
  // step (its steps vary, so a blow-up's last finite state is kept rather than replayed).
  std::unique_ptr<AdaptiveStepper> adaptive_;
  State previous_;
  // Dense output: on a smooth scene (the barrier, or nothing to project) the pair's steps do
  // not land on targets, and the state at a target inside a step is output_, a side step of
  // the pair from that step's start (previous_); under projection contacts they land.
  bool dense_ = false, has_output_ = false;
  State output_;
  bool advance_adaptive(double target);
  StepReport step_to(State& s, double t);  // dense output: one fixed step of the pair from s to t
  void judge_step(const StepReport& report, std::size_t actions_before, std::int64_t from_step, double from_t);
};

}  // namespace clothsim
