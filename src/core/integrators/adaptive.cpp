#include "adaptive.h"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

#include "integrator_kind.h"
#include "core/model/diagnostics.h"
#include "core/model/forces.h"

namespace clothsim {

namespace odeint = boost::numeric::odeint;

namespace adaptive_detail {  // named: AdaptiveStepper::Impl holds its types

using Vector = std::vector<double>;  // y = (x, v): 3B positions, then 3B velocities

// Bogacki & Shampine (1989), "A 3(2) pair of Runge-Kutta formulas", Appl. Math. Lett. 2(4):
//     c = (0, 1/2, 3/4, 1),  a21 = 1/2,  a32 = 3/4,  a4 = (2/9, 1/3, 4/9)
//     b (3rd order) = (2/9, 1/3, 4/9, 0),  b* (2nd order) = (7/24, 1/4, 1/3, 1/8)
// Odeint's generic pair takes b and the error weights b - b* = (-5/72, 1/12, 1/9, -1/8).
using Bs3Base = odeint::explicit_error_generic_rk<4, 3, 3, 2, Vector>;
struct Bs3 : Bs3Base {
  Bs3()
      : Bs3Base(boost::fusion::make_vector(boost::array<double, 1>{{0.5}}, boost::array<double, 2>{{0.0, 0.75}},
                                           boost::array<double, 3>{{2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0}}),
                boost::array<double, 4>{{2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0, 0.0}},
                boost::array<double, 4>{{-5.0 / 72.0, 1.0 / 12.0, 1.0 / 9.0, -1.0 / 8.0}},
                boost::array<double, 4>{{0.0, 0.5, 0.75, 1.0}}) {}
};
using Dopri5 = odeint::runge_kutta_dopri5<Vector>;
using Rkf78 = odeint::runge_kutta_fehlberg78<Vector>;

std::size_t coordinates(const Model& model) { return 3 * static_cast<std::size_t>(model.num_bodies()); }

void load(const State& state, Vector& y) {
  const std::size_t n = static_cast<std::size_t>(state.x.size());
  y.resize(2 * n);
  std::memcpy(y.data(), state.x.data(), n * sizeof(double));
  std::memcpy(y.data() + n, state.v.data(), n * sizeof(double));
}

void store(const Vector& y, State& state) {
  const std::size_t n = static_cast<std::size_t>(state.x.size());
  std::memcpy(state.x.data(), y.data(), n * sizeof(double));
  std::memcpy(state.v.data(), y.data() + n, n * sizeof(double));
}

// y' = (v, a(x, v)) with the state's inverse masses (pins change them at events). Odeint copies
// the system it is given, so this holds pointers to the scratch and the counter it fills.
struct Rhs {
  const Model* model;
  const Eigen::VectorXd* inv_mass;
  Eigen::Matrix3Xd *x, *v, *a;
  std::int64_t* evals;
  void operator()(const Vector& in, Vector& out, double /*t*/) const {
    const Eigen::Index bodies = model->num_bodies();
    const std::size_t n = coordinates(*model);
    *x = Eigen::Map<const Eigen::Matrix3Xd>(in.data(), 3, bodies);
    *v = Eigen::Map<const Eigen::Matrix3Xd>(in.data() + n, 3, bodies);
    accelerations(*model, *x, *v, *inv_mass, *a);
    std::memcpy(out.data(), in.data() + n, n * sizeof(double));
    std::memcpy(out.data() + n, a->data(), n * sizeof(double));
    ++*evals;
  }
};

// One fixed step of the pair's higher-order solution (no error estimate).
template <class Stepper>
StepStats fixed_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  StepStats stats;
  stats.start_strain = max_strain(model, state);
  Vector y;
  load(state, y);
  Stepper stepper;
  std::int64_t evals = 0;
  stepper.do_step(Rhs{&model, &state.inv_mass, &ws.x1, &ws.v1, &ws.a, &evals}, y, state.t, ctx.h);
  store(y, state);
  stats.force_evals = static_cast<int>(evals);
  return stats;
}

// A controlled pair behind one interface: Odeint's controlled steppers are templates.
struct AdaptivePair {
  virtual ~AdaptivePair() = default;
  virtual bool try_step(const Rhs& rhs, Vector& y, double& t, double& h) = 0;
  virtual void reset() = 0;
};

template <class Stepper, bool Fsal>
struct PairOf : AdaptivePair {
  using Checker = odeint::default_error_checker<double, odeint::range_algebra, odeint::default_operations>;
  using Controlled = odeint::controlled_runge_kutta<Stepper, Checker>;
  Controlled controlled;
  PairOf(double atol, double rtol) : controlled(Checker(atol, rtol)) {}
  bool try_step(const Rhs& rhs, Vector& y, double& t, double& h) override {
    return controlled.try_step(rhs, y, t, h) == odeint::success;
  }
  void reset() override {
    if constexpr (Fsal) controlled.reset();  // the stored derivative is of a state no longer there
  }
};

std::unique_ptr<AdaptivePair> make_pair(IntegratorKind kind, const AdaptiveDef& tol) {
  switch (kind) {
    case IntegratorKind::Bs3:
      return std::make_unique<PairOf<Bs3, false>>(tol.atol, tol.rtol);
    case IntegratorKind::Dopri5:
      return std::make_unique<PairOf<Dopri5, true>>(tol.atol, tol.rtol);
    case IntegratorKind::Rkf78:
      return std::make_unique<PairOf<Rkf78, false>>(tol.atol, tol.rtol);
    default:
      throw std::logic_error(std::string(integrator_name(kind)) + " is not an adaptive pair");
  }
}

}  // namespace adaptive_detail

using namespace adaptive_detail;

StepStats bs3_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  return fixed_step<Bs3>(model, state, ctx, ws);
}
StepStats dopri5_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  return fixed_step<Dopri5>(model, state, ctx, ws);
}
StepStats rkf78_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  return fixed_step<Rkf78>(model, state, ctx, ws);
}

struct AdaptiveStepper::Impl {
  const Model& model;
  std::unique_ptr<AdaptivePair> pair;
  double h_next;
  Vector y;
  Eigen::Matrix3Xd x, v, a;  // the right-hand side's scratch
};

AdaptiveStepper::AdaptiveStepper(const Model& model, IntegratorKind kind, const AdaptiveDef& control, double first_h)
    : impl_(std::make_unique<Impl>(Impl{model, make_pair(kind, control), first_h, {}, {}, {}, {}})) {}

AdaptiveStepper::~AdaptiveStepper() = default;

void AdaptiveStepper::restart() { impl_->pair->reset(); }

double AdaptiveStepper::proposed_step() const { return impl_->h_next; }

AdaptiveStep AdaptiveStepper::step(State& state, double limit) {
  Impl& m = *impl_;
  AdaptiveStep out;
  out.start_strain = max_strain(m.model, state);
  load(state, m.y);
  const Rhs rhs{&m.model, &state.inv_mass, &m.x, &m.v, &m.a, &out.force_evals};
  const double t0 = state.t;
  // The smallest step time can resolve here: below it t + h == t, and the controller is lost.
  const double h_min = 64.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t0));
  double h = m.h_next;
  bool landing = h >= limit - t0;
  if (landing) h = limit - t0;
  for (;;) {
    if (!(h >= h_min) || !std::isfinite(h)) {
      out.failed = true;
      return out;
    }
    double t = t0, h_try = h;
    if (m.pair->try_step(rhs, m.y, t, h_try)) {  // accepted: t = t0 + h, h_try the next proposal
      out.h = h;
      // A step shortened to land on a target resumes at the size proposed before shortening,
      // so frame times do not throttle the steps between them.
      m.h_next = landing ? std::max(h_try, m.h_next) : h_try;
      store(m.y, state);
      state.t = landing ? limit : t;
      return out;
    }
    ++out.rejected;  // refused: h_try is the controller's smaller trial
    h = h_try;
    m.h_next = h_try;
    landing = false;
  }
}

}  // namespace clothsim
