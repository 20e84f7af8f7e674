#include "reference.h"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <vector>

#include "core/model/forces.h"

namespace clothsim::analysis {

namespace odeint = boost::numeric::odeint;

bool smooth_scene(const Model& model) {
  return model.collision.model == ContactModel::Barrier || (model.num_spheres == 0 && !model.has_ground);
}

namespace {
using Vector = std::vector<double>;  // y = (x, v): 3B positions, then 3B velocities
using Dopri5 = odeint::runge_kutta_dopri5<Vector>;
using Dense = odeint::result_of::make_dense_output<Dopri5>::type;
constexpr double kFirstStep = 1e-5;  // s, a guess the controller corrects on its first step
}  // namespace

struct AdaptiveSolve::Impl {
  const Model& model;
  Dense dense;
  State state;
  Vector y;
  Eigen::Matrix3Xd x, v, a;  // the right-hand side's scratch
  std::int64_t force_evals = 0, steps = 0;
  bool fresh = true;  // (re)initialized at state.t, not stepped since: y is the state there
  bool stopped = false;
  std::optional<Divergence> divergence;
  std::function<bool()> stop;

  Impl(const Model& m, double tolerance)
      : model(m), dense(odeint::make_dense_output(tolerance, tolerance, Dopri5())), state(initial_state(m)) {
    load_y();
    dense.initialize(y, 0.0, kFirstStep);
  }

  std::size_t n() const { return 3 * static_cast<std::size_t>(model.num_bodies()); }

  void load_y() {
    y.resize(2 * n());
    std::memcpy(y.data(), state.x.data(), n() * sizeof(double));
    std::memcpy(y.data() + n(), state.v.data(), n() * sizeof(double));
  }
  void store_y(const Vector& from) {
    std::memcpy(state.x.data(), from.data(), n() * sizeof(double));
    std::memcpy(state.v.data(), from.data() + n(), n() * sizeof(double));
  }

  // y' = (v, a(x, v)), with the inverse masses the state has now (pins change them at events).
  void rhs(const Vector& in, Vector& out) {
    const Eigen::Index bodies = model.num_bodies();
    x = Eigen::Map<const Eigen::Matrix3Xd>(in.data(), 3, bodies);
    v = Eigen::Map<const Eigen::Matrix3Xd>(in.data() + n(), 3, bodies);
    accelerations(model, x, v, state.inv_mass, a);
    std::memcpy(out.data(), in.data() + n(), n() * sizeof(double));
    std::memcpy(out.data() + n(), a.data(), n() * sizeof(double));
    ++force_evals;
  }

  double next_event() const {
    return state.next_action < model.timeline.size() ? model.timeline[state.next_action].t
                                                     : std::numeric_limits<double>::infinity();
  }

  // Steps until the solve's current time reaches `goal`. False when stopped or diverged.
  bool step_past(double goal) {
    const auto system = [this](const Vector& in, Vector& out, double) { rhs(in, out); };
    while (dense.current_time() < goal) {
      if (stop && stop()) {
        stopped = true;
        return false;
      }
      try {
        dense.do_step(system);
      } catch (const odeint::step_adjustment_error& e) {
        divergence = Divergence{steps, dense.current_time(), std::string("the adaptive step failed: ") + e.what()};
        return false;
      }
      fresh = false;
      ++steps;
      const Vector& now = dense.current_state();
      if (!std::all_of(now.begin(), now.end(), [](double c) { return std::isfinite(c); })) {
        divergence = Divergence{steps, dense.current_time(), "non-finite state in the adaptive reference"};
        return false;
      }
    }
    return true;
  }

  // The state at t (inside the last step, or where the solve stands when fresh).
  void settle_at(double t) {
    if (!fresh) {
      Vector at(y.size());
      dense.calc_state(t, at);
      store_y(at);
    } else {
      store_y(y);
    }
    state.t = t;
  }

  bool advance_to(double t) {
    if (divergence || stopped) return !divergence;
    for (double te = next_event(); te <= t; te = next_event()) {
      // An event: stop exactly at it, apply it, and restart from there (piecewise).
      if (!step_past(te)) return !divergence;
      settle_at(te);
      apply_due_actions(model, state);
      load_y();
      dense.initialize(y, te, fresh ? kFirstStep : std::max(dense.current_time_step(), 1e-12));
      fresh = true;
    }
    if (!step_past(t)) return !divergence;
    settle_at(t);
    state.step = steps;
    divergence = check_bodies(model, state);
    return !divergence;
  }
};

AdaptiveSolve::AdaptiveSolve(const Model& model, double tolerance) : impl_(std::make_unique<Impl>(model, tolerance)) {}
AdaptiveSolve::~AdaptiveSolve() = default;
AdaptiveSolve::AdaptiveSolve(AdaptiveSolve&&) noexcept = default;
bool AdaptiveSolve::advance_to(double t) { return impl_->advance_to(t); }
void AdaptiveSolve::set_stop_check(std::function<bool()> stop) { impl_->stop = std::move(stop); }
bool AdaptiveSolve::stopped() const { return impl_->stopped; }
const std::optional<Divergence>& AdaptiveSolve::divergence() const { return impl_->divergence; }
const State& AdaptiveSolve::state() const { return impl_->state; }
std::int64_t AdaptiveSolve::steps() const { return impl_->steps; }
std::int64_t AdaptiveSolve::force_evals() const { return impl_->force_evals; }

AdaptiveReference::AdaptiveReference(const Model& model, double tolerance, double tightening)
    : model_(model),
      tolerance_(tolerance),
      tightening_(tightening),
      served_(model, tolerance),
      check_(model, tolerance / tightening) {
  check_.set_stop_check([this] { return abandon_.load(std::memory_order_relaxed); });
}

void AdaptiveReference::set_stop_check(const std::function<bool()>& stop) { served_.set_stop_check(stop); }

bool AdaptiveReference::advance_to(double t) {
  double check_cpu = 0.0;
  auto check = std::async(std::launch::async, [this, t, &check_cpu] {
    const double start = thread_cpu_seconds();
    const bool ok = check_.advance_to(t) && !check_.stopped();
    check_cpu = thread_cpu_seconds() - start;
    return ok;
  });
  const double cpu_start = thread_cpu_seconds();
  const bool served_ok = served_.advance_to(t) && !served_.stopped();
  if (!served_ok) abandon_.store(true, std::memory_order_relaxed);
  const bool check_ok = check.get();
  cpu_seconds_ += thread_cpu_seconds() - cpu_start + check_cpu;
  if (!served_ok || !check_ok) return !diverged();
  time_ = t;
  last_change_ = largest_particle_distance(model_, check_.state(), served_.state());
  estimated_error_ = std::max(estimated_error_, kEstimateFactor * last_change_);
  return true;
}

RunTotals AdaptiveReference::totals() const {
  RunTotals totals;
  totals.steps = served_.steps();
  totals.force_evals = served_.force_evals() + check_.force_evals();
  totals.cpu_seconds = totals.sim_seconds = cpu_seconds_;
  return totals;
}

StudyRun adaptive_run_to(const Model& model, double tolerance, double T, const std::function<bool()>& stop,
                         const Sampling& sampling) {
  AdaptiveSolve solve(model, tolerance);
  if (stop) solve.set_stop_check(stop);
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  bool going = true;
  for (std::size_t k = 0; going && k < sampling.times.size() && sampling.times[k] <= T; ++k) {
    going = solve.advance_to(sampling.times[k]) && !solve.stopped();
    if (going && sampling.at) sampling.at(k, solve.state());
  }
  if (going) solve.advance_to(T);
  StudyRun run;
  run.totals.cpu_seconds = thread_cpu_seconds() - cpu_start;
  run.totals.sim_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.totals.steps = solve.steps();
  run.totals.force_evals = solve.force_evals();
  run.stopped = solve.stopped();
  run.divergence = solve.divergence();
  run.finished = !run.stopped && !run.divergence;
  run.final_state = solve.state();
  return run;
}

double largest_particle_distance(const Model& model, const State& a, const State& b) {
  double largest = 0.0;
  for (int p = 0; p < model.num_particles; ++p)
    if (b.inv_mass[p] > 0.0) largest = std::max(largest, (a.x.col(p) - b.x.col(p)).norm());
  return largest;
}

}  // namespace clothsim::analysis
