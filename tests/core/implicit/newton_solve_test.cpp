// The Newton solve's records (newton_solve.h): the matrix-reuse phases and their transitions,
// the rent-against-buy of the sparse factor, and the trace, which goes only where the tool
// sends it and changes no number.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "test_support.h"
#include "core/implicit/newton_solve.h"
#include "core/run/simulation.h"
#include "scene/build_model.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::ImplicitEuler;

TEST(MatrixReuse, ATrialThatServesKeepsReuseAllowedAndTrusted) {
  MatrixReuse reuse;
  reuse.phase = MatrixReuse::Phase::Allowed;
  reuse.trusted = false;
  reuse.start_trial(2.0);
  EXPECT_EQ(reuse.phase, MatrixReuse::Phase::OnTrial);
  EXPECT_EQ(reuse.trial_from, 2.0);
  reuse.judge(true);
  EXPECT_EQ(reuse.phase, MatrixReuse::Phase::Allowed);
  EXPECT_TRUE(reuse.trusted);
  EXPECT_EQ(reuse.unserved, 0);
}

TEST(MatrixReuse, ATrialThatFailsBarsReuseAndIsNotChargedToTheBudget) {
  for (const bool judged : {true, false}) {
    MatrixReuse reuse;
    reuse.phase = MatrixReuse::Phase::Allowed;
    reuse.start_trial(1.0);
    if (judged) reuse.judge(false);
    else reuse.fail();  // no descent or no step
    EXPECT_EQ(reuse.phase, MatrixReuse::Phase::Barred);
    EXPECT_FALSE(reuse.allowed());
    EXPECT_FALSE(reuse.trusted);
    EXPECT_EQ(reuse.unserved, 1);
  }
}

TEST(StallWatch, CallsAStallOnlyAfterAWindowWithNeitherTheResidualHalvingNorPhiFalling) {
  StallWatch watch;
  const PotentialValue flat{-10.0, 100.0};
  EXPECT_FALSE(watch.stalled(0, 1.0, flat, 5));  // the first iterate marks
  for (int k = 1; k < 5; ++k) EXPECT_FALSE(watch.stalled(k, 0.9, flat, 5)) << k;
  EXPECT_TRUE(watch.stalled(5, 0.9, flat, 5));
  // The residual halving from the mark's is progress...
  EXPECT_FALSE(watch.stalled(6, 0.5, flat, 5));
  EXPECT_EQ(watch.mark, 6);
  // ...and so is Phi falling by more than a millionth of its size, whatever the residual.
  EXPECT_FALSE(watch.stalled(11, 0.9, PotentialValue{-10.001, 100.0}, 5));
  EXPECT_EQ(watch.mark, 11);
  // A fall of Phi within rounding is not.
  for (int k = 12; k < 16; ++k) EXPECT_FALSE(watch.stalled(k, 0.9, PotentialValue{-10.001 - 1e-12 * k, 100.0}, 5));
  EXPECT_TRUE(watch.stalled(16, 0.9, PotentialValue{-10.001 - 1e-12 * 16, 100.0}, 5));
}

// Frame-rate steps 1/240 .. 1/30 s with default settings: every step converges.
std::int64_t unconverged_steps(const std::string& scene, double h, std::vector<std::string> sets) {
  sets.push_back("dt=" + std::to_string(h));
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/" + scene, sets));
  clothsim::Run run(model, kKind, h);
  EXPECT_TRUE(run.advance_to(model.duration)) << scene << " h " << h;
  return run.totals().unconverged_steps;
}
constexpr double kFrameSteps[] = {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30};

TEST(ImplicitEuler, ConvergesAtEveryFrameRateStepOfTheStiffSceneAndTheDrapeByDefault) {
  for (const double h : kFrameSteps) {
    EXPECT_EQ(unconverged_steps("stiff.yaml", h, {}), 0) << "h " << h;
    EXPECT_EQ(unconverged_steps("drape.yaml", h, {"duration=2.5"}), 0) << "h " << h;
  }
}

TEST(ImplicitEuler, ConvergesAtEveryFrameRateStepOfStifferAndHeavierSheetsByDefault) {
  // k up to 1e7 N/m and particles up to 5 kg, falling on the stiff scene's ball and on a
  // small one (0.3 m): the cases that left steps at the old cap of 20 iterations.
  const std::vector<std::string> stiffer{"cloth.springs.structural.stiffness=1e7",
                                         "cloth.springs.shear.stiffness=1e7",
                                         "cloth.springs.bend.stiffness=1e6", "cloth.particle_mass=5",
                                         "duration=1.5"};
  std::vector<std::string> small_ball = stiffer;
  small_ball.push_back("spheres.0.radius=0.3");
  for (const double h : {1.0 / 60, 1.0 / 30}) {
    EXPECT_EQ(unconverged_steps("stiff.yaml", h, stiffer), 0) << "h " << h;
    EXPECT_EQ(unconverged_steps("stiff.yaml", h, small_ball), 0) << "h " << h;
  }
}

// The largest frame-to-frame rise of total energy over `frames` steps of h (one per frame), as a
// fraction of the starting energy (gravity's potential is measured from the ball's centre, so
// that is the energy the drop has to spend).
// single_from: ImplicitDef's (the float copy of the matrix from this many particles on).
double largest_rise(const std::vector<std::string>& sets, double h, int frames,
                    int single_from = ImplicitDef{}.single_from) {
  std::vector<std::string> all = sets;
  all.push_back("dt=" + std::to_string(h));
  Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml", all));
  model.implicit.single_from = single_from;
  clothsim::Run run(model, kKind, h);
  const double E0 = run.metrics().energies.total();
  double E = E0, rise = -1.0;
  for (int f = 1; f <= frames; ++f) {
    EXPECT_TRUE(run.advance_to(f * h));
    const double now = run.metrics().energies.total();
    rise = std::max(rise, (now - E) / std::abs(E0));
    E = now;
  }
  EXPECT_EQ(run.totals().unconverged_steps, 0);
  return rise;
}

TEST(ImplicitEuler, AStaticBallDoesNoWorkOnAStiffHeavySheetThatWrapsIt) {
  // A 35 x 35 sheet, k = 1e7 N/m, 1 kg a particle, on a 0.5 m ball at 1/30 s: at its impact
  // (step 9) held particles let go once and taken in again ended the step pulling, and the
  // ball did 2.2 kJ of work on the cloth (total energy +0.4 % in one frame).
  const std::vector<std::string> sets{"cloth.particles=[35, 35]", "cloth.springs.structural.stiffness=1e7",
                                      "cloth.springs.shear.stiffness=1e7", "cloth.springs.bend.stiffness=1e7",
                                      "cloth.particle_mass=1", "spheres.0.radius=0.5"};
  EXPECT_LE(largest_rise(sets, 1.0 / 30, 12), 1e-3);
}

TEST(ImplicitEuler, TheFloatCopyOfTheMatrixKeepsStiffDropsFromGainingEnergy) {
  // CG's mat-vec on the float copy (block_matrix.h), forced on at stiff.yaml's 15 x 15: the
  // stiffest drops of the test below. A first version rounded the diagonal blocks themselves
  // and gained 0.7 % of the energy in a frame at k = 1e7, 5 kg, h = 1/30.
  for (const char* mass : {"0.1", "5"}) {
    const std::vector<std::string> sets{"cloth.springs.structural.stiffness=1e7", "cloth.springs.shear.stiffness=1e7",
                                        std::string("cloth.particle_mass=") + mass, "spheres.0.radius=1",
                                        "cloth.center=[0, 1.5, 0]"};
    EXPECT_LE(largest_rise(sets, 1.0 / 30, 36, 0), 1e-3) << "mass " << mass;
  }
}

TEST(ImplicitEuler, ConvergedStepsWithAStaticBallAndGroundNeverGainEnergy) {
  // A family of drops on static colliders: stiffness, particle mass, ball radius, step. The
  // sheet starts 1.5 m up, clear of the largest ball's reach (one starting inside it is moved
  // out at the first step, which is a penetration undone, not work).
  for (const char* k : {"1e4", "1e6", "1e7"})
    for (const char* mass : {"0.1", "5"})
      for (const char* radius : {"0.3", "1"})
        for (const double h : {1.0 / 240, 1.0 / 30}) {
          const std::vector<std::string> sets{
              std::string("cloth.springs.structural.stiffness=") + k,
              std::string("cloth.springs.shear.stiffness=") + k, std::string("cloth.particle_mass=") + mass,
              std::string("spheres.0.radius=") + radius, "cloth.center=[0, 1.5, 0]"};
          EXPECT_LE(largest_rise(sets, h, static_cast<int>(std::lround(1.2 / h))), 1e-3)
              << "k " << k << " mass " << mass << " radius " << radius << " h " << h;
        }
}

TEST(ImplicitEuler, BaraffWitkinsStepStaysOneLinearisedSolve) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml",
                                             {"implicit.newton_max_iterations=1", "dt=0.03333333333333333"}));
  clothsim::Run run(model, kKind, model.dt);
  ASSERT_TRUE(run.advance_to(1.0));
  EXPECT_EQ(run.totals().newton_iterations, run.totals().steps);
}

TEST(NewtonTrace, GoesOnlyToTheSinkTheToolGivesAndChangesNoNumber) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml",
                                             {"dt=0.03333333333333333"}));
  State quiet = initial_state(model), traced = quiet;
  Workspace quiet_ws, traced_ws;
  std::vector<std::string> lines;
  traced_ws.newton_trace = [&lines](const char* line) { lines.emplace_back(line); };
  for (int n = 0; n < 10; ++n) {
    step(model, quiet, kKind, model.dt, quiet_ws);
    step(model, traced, kKind, model.dt, traced_ws);
  }
  EXPECT_EQ((quiet.x - traced.x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((quiet.v - traced.v).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front().rfind("newton step 0 start:", 0), 0u) << lines.front();
  int starts = 0;
  for (const std::string& line : lines) starts += line.find(" start: held ") != std::string::npos;
  EXPECT_EQ(starts, 10);
}

TEST(MultigridAccount, RebuildsAtANewHeldSetOrWhenTheStaleHierarchyDoublesTheIterations) {
  MultigridAccount account;
  account.fresh = 3;
  account.last = 8;
  EXPECT_FALSE(account.rebuild(0));  // the matrix it was built from is still the one in hand
  account.outdated = true;
  EXPECT_FALSE(account.rebuild(0));  // 8 <= 2 x 3 + 2: it still serves
  account.last = 9;
  EXPECT_TRUE(account.rebuild(0));
  account.outdated = false;
  EXPECT_TRUE(account.rebuild(1));   // another held set: the smoother would move held normals
}

// Rent against buy (factor_pays), in block-Jacobi iterations. Prices and unit costs below are
// the refined drape's at 32 x 32 and 256 x 256 (BENCHMARKS.md, CHOLMOD section): a factor of
// 182 and 2617 iterations, a factored iteration of 6 and 29.
TEST(FactorPays, BuysWhereTheSavingOverTheSolvesLeftExceedsThePrice) {
  // 150 Jacobi iterations left in this solve and 10 more solves of 100, against 4 factored
  // iterations of 6: saves 126 + 10 x 76 = 886 > 182.
  EXPECT_TRUE(factor_pays({182.0, 150.0, 100.0, 24.0, 10.0}));
  // The same at 256 x 256, where a fresh factor's solve costs 4 x 29 = 116 Jacobi iterations:
  // nothing to save however many solves are left.
  EXPECT_FALSE(factor_pays({2617.0, 150.0, 100.0, 116.0, 1000.0}));
  // A cheap solve with a dear factor: 2 solves left save 3 x 76 = 228 < 2617.
  EXPECT_FALSE(factor_pays({2617.0, 100.0, 100.0, 24.0, 2.0}));
  // Exactly the price is not enough: the factor must save more than it costs.
  EXPECT_FALSE(factor_pays({100.0, 60.0, 60.0, 10.0, 1.0}));
  EXPECT_TRUE(factor_pays({100.0, 60.1, 60.0, 10.0, 1.0}));
}

TEST(FactorAccount, ForecastsABlockJacobiSolvesRestFromItsRate) {
  // 10 iterations took the residual to 1e-2: 10 more reach 1e-4.
  EXPECT_NEAR(FactorAccount::remaining(10, 1e-2, 1e-4, 190.0), 10.0, 1e-9);
  EXPECT_EQ(FactorAccount::remaining(10, 1e-2, 1e-2, 190.0), 0.0);   // already there
  EXPECT_EQ(FactorAccount::remaining(10, 1.5, 1e-4, 190.0), 190.0);  // no progress: all it has
  EXPECT_EQ(FactorAccount::remaining(10, 0.9, 1e-8, 50.0), 50.0);    // at most its budget
}

TEST(FactorAccount, RenewsAFactorThatKeepsGrowingStaleButNotOneThatLevelledOff) {
  // stiff.yaml's pattern: a factored iteration costs 3.9, a factor 52; the solves after the
  // build took 1, 3, 7 and 12 iterations: 4 x (12 - 5.75) x 3.9 = 97 saved > 52.
  FactorAccount stiff;
  for (const int iterations : {1, 3, 7, 12}) stiff.record(iterations, true, 3.9);
  EXPECT_TRUE(factor_pays(stiff.renew(52.0)));
  // The refined drape at 256 x 256: 1, 30, 32 iterations of 29 against a factor of 2617.
  FactorAccount drape;
  for (const int iterations : {1, 30, 32}) drape.record(iterations, true, 29.0);
  EXPECT_FALSE(factor_pays(drape.renew(2617.0)));
  // Block-Jacobi solves count in their own account, not the factor's.
  drape.record(200, false, 1.0);
  EXPECT_EQ(drape.factored_solves, 3);
  EXPECT_EQ(drape.jacobi_work, 200.0);
}

TEST(FactorAccount, DropsAFactorDearerThanBlockJacobiAndCarriesOnlyOneThatPaid) {
  FactorAccount account;
  account.built = true;
  account.jacobi_forecast = 150.0;  // block Jacobi's mean solve when the factor was bought
  account.record(1, true, 29.0);
  EXPECT_FALSE(account.losing());   // one solve, on the factor's own matrix: too early to judge
  account.record(30, true, 29.0);   // 870 > 150
  EXPECT_TRUE(account.losing());
  EXPECT_FALSE(account.paid());     // mean 450 > 150: the next step rents first
  FactorAccount cheap;
  cheap.built = true;
  cheap.jacobi_forecast = 150.0;
  for (const int iterations : {1, 4, 6}) cheap.record(iterations, true, 6.0);
  EXPECT_FALSE(cheap.losing());
  EXPECT_TRUE(cheap.paid());        // mean 22 < 150: the next step starts with a factor
  EXPECT_FALSE(FactorAccount{}.paid());  // none built
}

TEST(NewtonSolve, AStepPreconditionedByTheVCycleIsTheBlockJacobiStepToTolerance) {
  // The drape at 24 x 24 (a grid of three levels), held on the ball from its first step: the
  // preconditioner changes CG's path, not the equation Newton solves.
  const auto run = [](const char* preconditioner) {
    const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                               {"cloth.particles=[24,24]", "dt=0.016666666666666666",
                                                std::string("implicit.preconditioner=") + preconditioner}));
    clothsim::Run r(model, kKind, model.dt);
    EXPECT_TRUE(r.advance_to(3 * model.dt));
    EXPECT_EQ(r.totals().unconverged_steps, 0);
    return std::make_pair(r.state().x, r.totals());
  };
  const auto [x_mg, mg] = run("multigrid");
  const auto [x_bj, bj] = run("block_jacobi");
  EXPECT_LE((x_mg - x_bj).cwiseAbs().maxCoeff(), 1e-6);  // m, against a 4 m sheet
  EXPECT_LT(mg.cg_iterations, bj.cg_iterations);
}

TEST(NewtonSolve, AStepPreconditionedByTheFactorIsTheBlockJacobiStepToTolerance) {
  // stiff.yaml at 1/60 s on the ball (steps 30-41, held contacts), each step taken twice from
  // the same State: with the factor (built at the step's first solve, then preconditioning
  // Newton's later matrices stale) and with block Jacobi. The factor changes CG's path and
  // cost, not the backward Euler step. (Through the landing the two runs part by millimetres
  // from step 15 on, before any factor is built: there Phi has several minima and the course,
  // block Jacobi's cap included, decides which one Newton finds; BENCHMARKS.md #37, round s36.)
  const auto model = [](const char* preconditioner) {
    return build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml",
                                  {"dt=0.016666666666666666",
                                   std::string("implicit.preconditioner=") + preconditioner}));
  };
  const Model factored = model("cholesky"), jacobi = model("block_jacobi");
  State state = initial_state(factored);
  Workspace ws, jacobi_ws;
  for (int n = 0; n < 30; ++n) step(factored, state, kKind, factored.dt, ws);
  double largest = 0.0;
  std::int64_t factorizations = 0, factored_cg = 0, jacobi_cg = 0;
  for (int n = 0; n < 12; ++n) {
    State other = state;
    const StepStats f = step(factored, state, kKind, factored.dt, ws).stats;
    const StepStats j = step(jacobi, other, kKind, jacobi.dt, jacobi_ws).stats;
    ASSERT_TRUE(f.converged && j.converged) << "step " << 30 + n;
    EXPECT_EQ(j.factorizations, 0);
    factorizations += f.factorizations;
    factored_cg += f.cg_iterations;
    jacobi_cg += j.cg_iterations;
    largest = std::max(largest, (state.x - other.x).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(factorizations, 0);
  EXPECT_LT(factored_cg, jacobi_cg);
  EXPECT_LE(largest, 1e-7);  // m, against a 3 m sheet (measured: 1e-9 to 6e-9)
}

TEST(TrustRadius, ShrinksOnAPoorRatioAndGrowsOnlyOnAGoodOneAtTheBoundary) {
  TrustRadius trust;
  EXPECT_TRUE(std::isinf(trust.radius));  // a step starts unbounded
  trust.update(0.5, 4.0, 4.0, true);      // fair: kept
  EXPECT_TRUE(std::isinf(trust.radius));
  trust.update(0.1, 4.0, 4.0, false);     // poor: a quarter of the step tried
  EXPECT_EQ(trust.radius, 1.0);
  trust.update(0.1, 4.0, 0.25, false);    // poor, and the line search took less still: that
  EXPECT_EQ(trust.radius, 0.25);
  trust.update(0.9, 0.25, 0.25, false);   // good but inside the radius: kept
  EXPECT_EQ(trust.radius, 0.25);
  trust.update(0.9, 0.25, 0.25, true);    // good on the boundary: doubled
  EXPECT_EQ(trust.radius, 0.5);
  trust.update(std::nan(""), 0.5, 0.5, true);  // a trial whose Phi was not finite: shrunk
  EXPECT_EQ(trust.radius, 0.125);
  trust.update(-std::numeric_limits<double>::infinity(), 0.5, 0.5, true);
  EXPECT_EQ(trust.radius, 0.125);
}

TEST(NewtonSolve, TheTrustRegionChangesTheCourseNotTheStepsSolution) {
  // The refined drape at 48 x 48 (particle mass (32/48)^2 kg), where the sheet buckles on the
  // ball and CG meets negative curvature: with and without the trust radius, each step
  // converges, and the states agree to what the Newton tolerance allows.
  const auto run = [](bool trust_region) {  // (from 128 x 128 by default)
    Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                         {"cloth.particles=[48,48]", "cloth.particle_mass=0.4444444444444444",
                                          "dt=0.016666666666666666", "implicit.preconditioner=block_jacobi"}));
    model.implicit.trust_region_from = trust_region ? 0 : std::numeric_limits<int>::max();
    clothsim::Run r(model, kKind, model.dt);
    EXPECT_TRUE(r.advance_to(6 * model.dt));
    EXPECT_EQ(r.totals().unconverged_steps, 0);
    return std::make_pair(r.state().x, r.totals());
  };
  const auto [x_tr, tr] = run(true);
  const auto [x_ls, ls] = run(false);
  EXPECT_LE((x_tr - x_ls).cwiseAbs().maxCoeff(), 1e-5);  // m, against a 4 m sheet
  EXPECT_NE(tr.cg_iterations, ls.cg_iterations);  // the radius and forcing term did act
}

TEST(CapParticleSteps, ShortensOnlyTheParticlesBeyondTheCapAndKeepsTheirDirections) {
  Eigen::Matrix3Xd d(3, 4);
  d << 3, 0.1, 0, 9,
       4, 0.2, 0, 9,
       0, 0.0, 0, 9;  // lengths 5, 0.22, 0; the last column a sphere (not a particle)
  const Eigen::Matrix3Xd before = d;
  EXPECT_EQ(particle_steps_over(d, 3, 1.0), 1);  // counted without a change
  EXPECT_EQ(d, before);
  EXPECT_EQ(particle_steps_over(d, 3, 0.2), 2);
  EXPECT_EQ(cap_particle_steps(d, 3, 1.0), 1);
  EXPECT_NEAR(d.col(0).norm(), 1.0, 1e-15);
  EXPECT_NEAR(d.col(0).dot(before.col(0)) / before.col(0).norm(), 1.0, 1e-15);  // same direction
  EXPECT_EQ(d.col(1), before.col(1));
  EXPECT_EQ(d.col(2), before.col(2));
  EXPECT_EQ(d.col(3), before.col(3));  // beyond P: untouched
  EXPECT_EQ(cap_particle_steps(d, 3, 1.0), 0);  // once capped, within the cap
  EXPECT_EQ(particle_steps_over(d, 3, 1.0), 0);
}

TEST(NewtonSolve, TheDirectionCapChangesTheCourseNotTheStepsSolution) {
  // The refined drape at 48 x 48 with the trust region on, where particles at the ball's rim
  // take long directions: with and without a per-particle cap (a tight one, so that it acts
  // on this small sheet), each step converges, and the states agree to what the Newton
  // tolerance allows.
  const auto run = [](double cap) {
    Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                         {"cloth.particles=[48,48]", "cloth.particle_mass=0.4444444444444444",
                                          "dt=0.016666666666666666", "implicit.preconditioner=block_jacobi"}));
    model.implicit.trust_region_from = 0;
    model.implicit.direction_cap = cap;
    clothsim::Run r(model, kKind, model.dt);
    EXPECT_TRUE(r.advance_to(6 * model.dt));
    EXPECT_EQ(r.totals().unconverged_steps, 0);
    return std::make_pair(r.state().x, r.totals());
  };
  const auto [x_cap, cap] = run(0.02);
  const auto [x_free, free] = run(0.0);
  EXPECT_LE((x_cap - x_free).cwiseAbs().maxCoeff(), 1e-5);  // m, against a 4 m sheet
  EXPECT_NE(cap.cg_iterations, free.cg_iterations);  // the cap did act
}

}  // namespace
}  // namespace clothsim::testing
