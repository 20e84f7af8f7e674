#include "study/tables/csv_tables.h"

#include <cmath>

#include "io/csv_cells.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::analysis {

std::string CsvCell::spelled() const {
  switch (kind) {
    case Kind::Number: return csv_number(number);
    case Kind::Integer: return std::to_string(integer);
    case Kind::Text: break;
  }
  return csv_text(text);
}

std::string CsvTable::header() const {
  std::string out;
  for (std::size_t i = 0; i < columns.size(); ++i) out += (i ? "," : "") + columns[i];
  return out + "\n";
}

std::string CsvTable::row_text(std::size_t r) const {
  std::string out;
  for (std::size_t i = 0; i < rows[r].size(); ++i) out += (i ? "," : "") + rows[r][i].spelled();
  return out + "\n";
}

std::string CsvTable::text() const {
  std::string out = header();
  for (std::size_t r = 0; r < rows.size(); ++r) out += row_text(r);
  return out;
}

namespace {

using C = CsvCell;
// A number, or an empty cell where it does not apply (diverged_at of a run that did not).
CsvCell number_if(bool applies, double v) { return applies ? C::of(v) : C::words(""); }

}  // namespace

CsvTable work_precision_table(const WorkPrecisionResult& r, const std::vector<std::string>& names) {
  CsvTable t;
  t.columns = {"integrator", "dt", "steps", "force_evals", "newton_iterations", "cg_iterations", "wall_seconds",
               "cpu_seconds", "rms_error", "max_error", "diverged", "diverged_at", "reason", "duration",
               "reference_dt", "reference_change", "unconverged_steps", "wrong", "wrong_at", "wrong_reason",
               "unresolved", "tolerance", "rejected_steps", "error_measure", "rms_error_at_end",
               "max_error_at_end", "rms_error_over_time", "max_error_over_time", "samples"};
  // An error within reach of the reference's own is no number (unresolved, study/reference.h).
  for (const WorkPrecisionPoint& p : r.points)
    t.rows.push_back({C::words(names[p.lane]), C::of(p.dt), C::whole(p.steps), C::whole(p.force_evals),
                      C::whole(p.newton_iterations), C::whole(p.cg_iterations), C::of(p.wall_seconds),
                      C::of(p.cpu_seconds), C::of(p.unresolved ? NAN : p.rms_error),
                      C::of(p.unresolved ? NAN : p.max_error), C::whole(p.diverged ? 1 : 0),
                      number_if(p.diverged, p.diverged_at), C::words(p.reason), C::of(r.duration),
                      C::of(r.reference.dt), C::of(r.reference.finished ? r.reference.change_rms : NAN),
                      C::whole(p.unconverged_steps), C::whole(p.wrong ? 1 : 0), number_if(p.wrong, p.wrong_at),
                      C::words(p.wrong_reason), C::whole(p.unresolved ? 1 : 0),
                      number_if(p.tolerance > 0.0, p.tolerance), C::whole(p.rejected_steps),
                      C::words(r.reference.over_time ? "time" : "end"), C::of(p.unresolved ? NAN : p.rms_error_at_end),
                      C::of(p.unresolved ? NAN : p.max_error_at_end), C::of(p.unresolved ? NAN : p.rms_error_over_time),
                      C::of(p.unresolved ? NAN : p.max_error_over_time), C::whole(p.samples)});
  return t;
}

std::string frame_steps_text(const StabilityLimit& l) {
  std::string out;
  for (const FrameStepResult& r : l.frame_steps) out += (out.empty() ? "" : "; ") + frame_step_text(r);
  return out;
}

CsvTable stability_table(const std::vector<StabilityLimit>& limits, const StabilitySpec& spec, const std::string& param,
                         const std::vector<std::string>& names) {
  CsvTable t;
  t.columns = {"param", "value", "integrator", "outcome", "stable_dt", "unstable_dt", "trials", "cpu_seconds",
               "w_max", "c_max", "dt_springs", "dt_with_damping", "duration", "min_dt", "max_dt", "precision",
               "reason", "failure", "frame_steps"};
  for (const StabilityLimit& l : limits)
    t.rows.push_back({C::words(param), C::of(l.value), C::words(names[l.lane]), C::words(outcome_name(l.outcome)),
                      C::of(l.stable_dt), C::of(l.unstable_dt), C::whole(l.trials), C::of(l.cpu_seconds),
                      C::of(l.estimate.w_max), C::of(l.estimate.c_max), C::of(l.estimate.dt_springs()),
                      C::of(l.estimate.dt_with_damping()), C::of(spec.duration), C::of(spec.min_dt),
                      C::of(spec.max_dt), C::of(spec.precision), C::words(l.reason),
                      C::words(failure_name(l.failure)), C::words(frame_steps_text(l))});
  return t;
}

CsvTable convergence_table(const std::vector<ConvergencePoint>& points, const std::string& scene) {
  CsvTable t;
  t.columns = {"scene", "method", "state", "t", "iterations", "rms_distance", "max_distance", "gradient_norm",
               "cpu_seconds", "wrong"};
  for (const ConvergencePoint& p : points)
    t.rows.push_back({C::words(scene), C::words(std::string(integrator_name(p.method))), C::whole(p.state), C::of(p.t),
                      C::whole(p.iterations), C::of(p.rms), C::of(p.max), C::of(p.gradient), C::of(p.cpu_seconds),
                      C::words(p.wrong)});
  return t;
}

}  // namespace clothsim::analysis
