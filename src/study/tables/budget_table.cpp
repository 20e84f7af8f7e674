#include "budget_table.h"

#include <cmath>

namespace clothsim::analysis {

CsvTable budget_table(const BudgetResult& r, const std::vector<std::string>& lanes) {
  using C = CsvCell;
  CsvTable t;
  t.columns = {"solver", "lane", "budget", "substeps", "iterations", "dt", "fps", "duration", "frames", "steps",
               "force_evals", "solver_iterations", "newton_iterations", "cg_iterations", "wall_seconds",
               "cpu_seconds", "max_error", "max_error_t", "final_error", "max_strain", "energy_lost_per_s",
               "unresolved", "diverged", "diverged_at", "reason", "unconverged_steps", "max_residual", "wrong",
               "wrong_at", "wrong_reason", "reference_error", "reference_max_strain", "reference_energy_lost_per_s",
               "colliders_move"};
  const BudgetReference& ref = r.reference;
  const auto number_if = [](bool given, double v) { return given ? C::of(v) : C::words(""); };
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const BudgetPoint& p = r.points[i];
    const RunTotals& k = p.totals;
    // An error within reach of the reference's own is no number (unresolved), as bench's CSV has it.
    t.rows.push_back({C::words(solver_name(r.spec, p.solver)), C::words(i < lanes.size() ? lanes[i] : ""),
                      C::whole(r.spec.budget), C::whole(p.substeps), C::whole(p.iterations), C::of(p.dt),
                      C::of(r.spec.fps), C::of(r.spec.duration), C::whole(p.frames), C::whole(k.steps),
                      C::whole(k.force_evals), C::whole(k.solver_iterations), C::whole(k.newton_iterations),
                      C::whole(k.cg_iterations), C::of(k.sim_seconds), C::of(k.cpu_seconds),
                      C::of(p.unresolved ? NAN : p.max_error), C::of(p.unresolved ? NAN : p.max_error_t),
                      C::of(p.unresolved ? NAN : p.final_error), C::of(p.max_strain), C::of(p.energy_lost_per_second),
                      C::whole(p.unresolved ? 1 : 0), C::whole(p.diverged ? 1 : 0), number_if(p.diverged, p.diverged_at),
                      C::words(p.reason), C::whole(k.unconverged_steps), C::of(k.max_residual),
                      C::whole(p.wrong() ? 1 : 0), number_if(p.wrong(), p.wrong() ? k.wrong->t : 0.0),
                      C::words(p.wrong() ? k.wrong->reason : ""), C::of(ref.estimated_error), C::of(ref.max_strain),
                      C::of(ref.energy_lost_per_second), C::whole(r.colliders_move ? 1 : 0)});
  }
  return t;
}

}  // namespace clothsim::analysis
