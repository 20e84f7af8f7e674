#include "run_outputs.h"

#include <algorithm>
#include <cinttypes>

#include "io/csv_cells.h"  // csv_text, csv_number: shortest exact form

namespace clothsim::clip {

MetricsWriter::MetricsWriter(const std::string& path, const Model& model, IntegratorKind kind, double dt)
    : file_(path) {
  std::fputs("step,t,kinetic,spring_potential,gravity_potential,total_energy,max_strain,contacts,"
             "force_evals,newton_iterations,cg_iterations,residual,converged,scene,integrator,dt,step_size,"
             "rejected_steps\n",
             file_.stream());
  run_columns_ = "," + csv_text(model.name) + "," + method_name(kind, model.implicit) + "," + csv_number(dt);
}

void MetricsWriter::row(const FrameMetrics& m) {
  std::fprintf(file_.stream(),
               "%" PRId64 ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%" PRId64 ",%" PRId64 ",%" PRId64
               ",%.6g,%d",
               m.step, m.t, m.energies.kinetic, m.energies.spring, m.energies.gravity,
               m.energies.total(), m.max_strain, m.contacts, m.force_evals, m.newton_iterations,
               m.cg_iterations, m.residual, m.converged ? 1 : 0);
  // Written whole, not through %s: a cell is never cut at a byte it holds.
  std::fwrite(run_columns_.data(), 1, run_columns_.size(), file_.stream());
  // The step the run took last and its refused trials: an adaptive pair's own; a fixed-step
  // lane's dt and 0.
  const std::string step = "," + csv_number(m.step_size) + "," + std::to_string(m.rejected_steps) + "\n";
  std::fwrite(step.data(), 1, step.size(), file_.stream());
}

PngText frame_metadata(const Model& model, IntegratorKind kind, double dt) {
  char dt_text[32];
  std::snprintf(dt_text, sizeof dt_text, "%.6g", dt);
  return {{"scene", model.name}, {"source", model.source},
          {"integrator", method_name(kind, model.implicit)}, {"dt", dt_text},
          {"software", "clothsim " CLOTHSIM_VERSION}};
}

RunFiles::RunFiles(const std::vector<std::string>& finished, const std::vector<std::string>& after) {
  for (const std::string& path : finished)
    if (!path.empty()) kept_.push_back(path);
  for (const std::string& path : after)
    if (!path.empty()) pending_.push_back(path);
}

void RunFiles::write(const std::string& path, const std::function<void()>& write_file) {
  if (path.empty()) return;
  try {
    write_file();
  } catch (const RuntimeFailure& e) {
    // A write the signal broke off (a FIFO with no reader yet: EINTR) is said as the signal's stop.
    if (interrupted())
      throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + " while writing " + path + "; " +
                           what_stays(kept_, pending_));
    throw RuntimeFailure(std::string(e.what()) + "; " + what_stays(kept_, pending_));
  }
  kept_.push_back(path);
  pending_.erase(std::find(pending_.begin(), pending_.end(), path));
}

void write_state_csv(const std::string& path, const Model& model, const State& state) {
  AtomicFile file(path);
  std::fputs("id,x,y,z,vx,vy,vz\n", file.stream());
  for (int p = 0; p < model.num_particles; ++p)
    std::fprintf(file.stream(), "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", p, state.x(0, p),
                 state.x(1, p), state.x(2, p), state.v(0, p), state.v(1, p), state.v(2, p));
  file.commit();
}

}  // namespace clothsim::clip
