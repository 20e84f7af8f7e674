// The studies' CSV tables (study/csv_tables.h), which the CLI's --csv and the Python module's
// DataFrames both read: the columns in order, and each cell spelled as the CSV has it.
#include "study/tables/csv_tables.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace clothsim;
using namespace clothsim::analysis;

TEST(WorkPrecisionTable, HasBenchsColumnsAndSpellsARowAsTheCsvDoes) {
  WorkPrecisionResult r;
  r.duration = 1.0;
  r.reference.dt = 1.25e-4;
  r.reference.finished = false;  // no estimate: "nan"
  WorkPrecisionPoint p;
  p.integrator = IntegratorKind::Rk4;
  p.lane = 0;
  p.dt = 0.01;
  p.steps = 100;
  p.force_evals = 400;
  p.finished = true;
  p.rms_error = p.rms_error_over_time = 1.5e-6;
  p.max_error = p.max_error_over_time = 3e-6;
  p.rms_error_at_end = 1e-6, p.max_error_at_end = 2e-6;
  p.samples = 25;
  r.points.push_back(p);
  p.lane = 1;
  p.diverged = true;  // a diverged run: its time, and its reason quoted where it holds a comma
  p.diverged_at = 0.25;
  p.reason = "energy 1e9 J, past the bound";
  r.points.push_back(p);
  const CsvTable t = work_precision_table(r, {"rk4", "xpbd:10"});
  EXPECT_EQ(t.header(),
            "integrator,dt,steps,force_evals,newton_iterations,cg_iterations,wall_seconds,cpu_seconds,"
            "rms_error,max_error,diverged,diverged_at,reason,duration,reference_dt,reference_change,"
            "unconverged_steps,wrong,wrong_at,wrong_reason,unresolved,tolerance,rejected_steps,error_measure,"
            "rms_error_at_end,max_error_at_end,rms_error_over_time,max_error_over_time,samples\n");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.row_text(0),
            "rk4,0.01,100,400,0,0,0,0,1.5e-06,3e-06,0,,,1,0.000125,nan,0,0,,,0,,0,time,1e-06,2e-06,1.5e-06,3e-06,25\n");
  EXPECT_EQ(t.row_text(1),
            "xpbd:10,0.01,100,400,0,0,0,0,1.5e-06,3e-06,1,0.25,\"energy 1e9 J, past the bound\",1,0.000125,nan,0,0,,,0,,"
            "0,time,1e-06,2e-06,1.5e-06,3e-06,25\n");
  EXPECT_EQ(t.text(), t.header() + t.row_text(0) + t.row_text(1));
}

TEST(WorkPrecisionTable, AnUnresolvedErrorIsNoNumber) {
  WorkPrecisionResult r;
  WorkPrecisionPoint p;
  p.unresolved = true;  // within reach of the reference's own error
  p.rms_error = 1e-9;
  p.max_error = 2e-9;
  r.points.push_back(p);
  const CsvTable t = work_precision_table(r, {"rk4"});
  EXPECT_TRUE(std::isnan(t.rows[0][8].number));
  EXPECT_TRUE(std::isnan(t.rows[0][9].number));
  EXPECT_EQ(t.rows[0][8].spelled(), "nan");
  EXPECT_EQ(t.rows[0][20].integer, 1);
}

TEST(StabilityTable, HasStabilitysColumnsAndEveryCellOfARow) {
  StabilitySpec spec;
  spec.duration = 400;
  spec.min_dt = 1e-3;
  spec.max_dt = 1;
  spec.precision = 0.02;
  StabilityLimit l;
  l.integrator = IntegratorKind::SymplecticEuler;
  l.value = 100;
  l.outcome = StabilityOutcome::Bracketed;
  l.stable_dt = 0.198;
  l.unstable_dt = 0.2;
  l.trials = 9;
  const CsvTable t = stability_table({l}, spec, "ks", {"symplectic_euler"});
  ASSERT_EQ(t.columns.size(), 19u);
  EXPECT_EQ(t.columns.front(), "param");
  EXPECT_EQ(t.columns.back(), "frame_steps");
  ASSERT_EQ(t.rows.size(), 1u);
  ASSERT_EQ(t.rows[0].size(), t.columns.size());
  const std::string row = t.row_text(0);
  EXPECT_EQ(row.rfind("ks,100,symplectic_euler,bracketed,0.198,0.2,9,", 0), 0u) << row;
}

TEST(ConvergenceTable, HasConvergesColumnsAndItsRows) {
  ConvergencePoint p;
  p.method = IntegratorKind::Vbd;
  p.state = 2;
  p.t = 0.5;
  p.iterations = 10;
  p.rms = 1e-3;
  p.max = 2e-3;
  p.gradient = 0.5;
  const CsvTable t = convergence_table({p}, "drape");
  EXPECT_EQ(t.header(), "scene,method,state,t,iterations,rms_distance,max_distance,gradient_norm,cpu_seconds,wrong\n");
  EXPECT_EQ(t.row_text(0), "drape,vbd,2,0.5,10,0.001,0.002,0.5,0,\n");
}
