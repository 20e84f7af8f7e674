#include "simulation.h"

#include "core/model/barrier_contacts.h"  // uses_barrier

#include <time.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim {
namespace {
// An iterative solver's step reports its iterations as newton_iterations; the totals keep
// them apart, weighed by the solver's own cost per iteration.
void add_solver_iterations(RunTotals& t, IntegratorKind kind, std::int64_t iterations) {
  const IntegratorInfo& info = integrator_info(kind);
  if (info.iterations != IterationControl::Solver) return;
  t.solver_iterations += iterations;
  t.solver_iteration_passes = info.passes_per_iteration;
}
}  // namespace

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

StepReport step(const Model& model, const MethodSettings& settings, State& state, IntegratorKind kind, double h,
                Workspace& ws) {
  StepReport report;
  report.stats = integrate(kind, model, settings, state, h, ws);  // forces are evaluated in here
  report.contacts = resolve_collisions(model, state);             // once, after the whole step
  state.step += 1;                                                 // time: counted, not accumulated,
  state.t = static_cast<double>(state.step) * h;                   // so t stays exact over 1e5 steps
  apply_due_actions(model, state);                                 // events: pins, sphere keyframes
  return report;
}

StepReport step(const Model& model, State& state, IntegratorKind kind, double h, Workspace& ws) {
  return step(model, model.method_defaults(), state, kind, h, ws);
}

Run::Run(const Model& model, IntegratorKind kind, double dt, const MethodSettings& settings)
    : model_(model), kind_(kind), dt_(dt), settings_(settings), state_(initial_state(model)) {
  if (integrator_info(kind).adaptive) {
    adaptive_ = std::make_unique<AdaptiveStepper>(model, kind, settings_.adaptive, dt);
    dense_ = uses_barrier(model) || (model.num_spheres == 0 && !model.has_ground);
  }
  start_strain_ = max_strain(model_, state_);
  energy_every_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(kWrongEnergyEvery / dt_ + 1e-9)));
  record_energy(energy_, compute_energies(model_, state_).total(), true);
}

// The WRONG verdict's evidence from the step just taken: the strain its first force pass
// measured, work done by an event, and, every energy_every_ steps, the total energy.
void Run::judge_step(const StepReport& report, std::size_t actions_before, std::int64_t from_step, double from_t) {
  if (state_.next_action != actions_before) work_since_sample_ = true;
  if (!totals_.wrong) totals_.wrong = check_over_stretched(report.stats.start_strain, start_strain_, from_step, from_t);
  if (state_.step % energy_every_ != 0) return;
  record_energy(energy_, compute_energies(model_, state_).total(), work_since_sample_ || external_work(model_, state_));
  work_since_sample_ = false;
  if (!totals_.wrong) totals_.wrong = check_energy_made(model_, energy_, state_.step, state_.t);
}

bool Run::advance_to(double target) {
  if (divergence_) return false;
  if (stopped_) return true;
  if (adaptive_) return advance_adaptive(target);
  checkpoint_ = state_;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  const double tolerance = 1e-6 * dt_;
  bool stepped = false;
  while (state_.t < target - tolerance) {
    if (stop_ && stop_()) {
      stopped_ = true;
      break;
    }
    const std::int64_t from_step = state_.step;
    const double from_t = state_.t;
    const std::size_t actions_before = state_.next_action;
    last_ = step(model_, settings_, state_, kind_, dt_, ws_);
    stepped = true;
    ++totals_.steps;
    totals_.last_step = totals_.smallest_step = totals_.largest_step = dt_;
    totals_.force_evals += last_.stats.force_evals;
    totals_.newton_iterations += last_.stats.newton_iterations;
    totals_.cg_iterations += last_.stats.cg_iterations;
    totals_.factorizations += last_.stats.factorizations;
    totals_.assemblies += last_.stats.assemblies;
    totals_.factored_cg_iterations += last_.stats.factored_cg_iterations;
    add_solver_iterations(totals_, kind_, last_.stats.newton_iterations);
    totals_.max_strain = std::max(totals_.max_strain, last_.stats.start_strain);
    if (!last_.stats.converged) ++totals_.unconverged_steps;
    totals_.max_residual = std::max(totals_.max_residual, last_.stats.residual);
    totals_.contact_constraints += last_.stats.contact_constraints;
    if (integrator_info(kind_).counts_safety_projections) {
      totals_.safety_projections += last_.contacts.projected;
      if (last_.contacts.projected > 0) ++totals_.projected_steps;
    }
    // Every step: the state it started from against the strain bound (its first force pass
    // measured it), then the state it reached against the rest. Nothing here depends on
    // which outputs are watching, so a run diverges at the same step whatever is written.
    divergence_ = check_strain(model_, last_.stats.start_strain, from_step, from_t);
    if (!divergence_) divergence_ = check_bodies(model_, state_);
    if (divergence_) break;
    judge_step(last_, actions_before, from_step, from_t);
  }
  // The state handed out at the target has had no force pass yet: measure its strain here,
  // so what is shown or written is checked. The step after would report the same step.
  if (!divergence_ && stepped) divergence_ = check_divergence(model_, state_);
  totals_.sim_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  totals_.cpu_seconds += thread_cpu_seconds() - cpu_start;
  return !divergence_;
}

// An adaptive pair's advance (adaptive.h): the phases of step() around a step its controller
// chose, shortened to land on every timeline event (and on the target under projection):
//     accepted step -> collisions -> time -> events -> divergence check
// A projection that moved a particle, or an event, changed the state outside the ODE: the pair
// restarts from the new state. On a smooth scene (dense_) the steps cross the target, so what
// is output does not change the steps taken (SciML's saveat; Odeint's dense output): the state
// at the target is one step of the pair itself from the start of the step that crossed it, of
// the pair's own order, its force evaluations counted.
bool Run::advance_adaptive(double target) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  const double tolerance = 1e-12 * std::max(1.0, std::abs(target));
  bool stepped = false;
  while (state_.t < target - tolerance) {
    if (stop_ && stop_()) {
      stopped_ = true;
      break;
    }
    const std::int64_t from_step = state_.step;
    const double from_t = state_.t;
    const std::size_t actions_before = state_.next_action;
    const double event = state_.next_action < model_.timeline.size() ? model_.timeline[state_.next_action].t
                                                                      : std::numeric_limits<double>::infinity();
    const double free = dense_ ? std::numeric_limits<double>::infinity() : target;
    const double limit = event > state_.t + tolerance ? std::min(free, event) : free;
    previous_ = state_;
    const AdaptiveStep s = adaptive_->step(state_, limit);
    totals_.force_evals += s.force_evals;
    totals_.rejected_steps += s.rejected;
    if (s.failed) {
      divergence_ = Divergence{state_.step, state_.t,
                               "the adaptive step fell below what time resolves (" + std::to_string(s.rejected) +
                                   " trials refused): the tolerance cannot be met here"};
      break;
    }
    stepped = true;
    last_ = StepReport{};
    last_.stats.force_evals = s.force_evals;
    last_.stats.start_strain = s.start_strain;
    last_.contacts = resolve_collisions(model_, state_);  // once, after the accepted step
    state_.step += 1;
    apply_due_actions(model_, state_);
    // Under the barrier, contact is a force inside the ODE and resolve_collisions only counts
    // it; under projection a resolved contact moved the state after the step.
    const bool contact = !uses_barrier(model_) && (last_.contacts.total() > 0 || last_.contacts.projected > 0);
    if (contact || state_.next_action != actions_before) adaptive_->restart();
    if (contact) ++totals_.projected_steps;
    ++totals_.steps;
    totals_.last_step = s.h;
    totals_.smallest_step = totals_.steps == 1 ? s.h : std::min(totals_.smallest_step, s.h);
    totals_.largest_step = std::max(totals_.largest_step, s.h);
    totals_.max_strain = std::max(totals_.max_strain, s.start_strain);
    divergence_ = check_strain(model_, s.start_strain, from_step, from_t);
    if (!divergence_) divergence_ = check_bodies(model_, state_);
    if (divergence_) break;
    judge_step(last_, actions_before, from_step, from_t);
  }
  if (!divergence_ && stepped) divergence_ = check_divergence(model_, state_);
  // The target inside the last step: a side step to it (landed on exactly: state_ itself).
  has_output_ = dense_ && !divergence_ && !stopped_ && state_.t > target + tolerance;
  if (has_output_) {
    output_ = previous_;
    totals_.force_evals += step_to(output_, target).stats.force_evals;
  }
  totals_.sim_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  totals_.cpu_seconds += thread_cpu_seconds() - cpu_start;
  return !divergence_;
}

StepReport Run::step_to(State& s, double t) {
  StepReport report;
  report.stats = integrate(kind_, model_, settings_, s, t - s.t, ws_);  // the pair's own solution at that h
  report.contacts = resolve_collisions(model_, s);            // counts only: the scene is smooth
  s.t = t;
  return report;
}

namespace {
bool all_finite(const State& s) { return s.x.allFinite() && s.v.allFinite(); }
}  // namespace

State Run::last_finite_state() const {
  if (!divergence_) return state_;
  if (adaptive_) return all_finite(state_) ? state_ : previous_;
  // The named state itself when finite, else the one before: replay to the earlier of the
  // two only when needed (the replay's own result tells which).
  const std::int64_t named = divergence_->step;
  State s = checkpoint_;
  Workspace ws;
  State previous = s;
  while (s.step < named) {
    previous = s;
    step(model_, settings_, s, kind_, dt_, ws);
  }
  if (all_finite(s)) return s;
  return previous.step < s.step ? previous : checkpoint_;
}

FrameMetrics Run::metrics() const {
  FrameMetrics m;
  const State& at = state();  // at the target: an adaptive pair's dense output there
  m.step = at.step;
  m.t = at.t;
  m.energies = compute_energies(model_, at);
  m.max_strain = max_strain(model_, at);
  m.contacts = last_.contacts.total() + last_.stats.contact_constraints;  // after and inside the solve
  m.force_evals = totals_.force_evals;
  m.newton_iterations = totals_.newton_iterations;
  m.cg_iterations = totals_.cg_iterations;
  m.residual = last_.stats.residual;
  m.converged = last_.stats.converged;
  m.step_size = totals_.steps > 0 ? totals_.last_step : dt_;
  m.rejected_steps = totals_.rejected_steps;
  return m;
}

}  // namespace clothsim
