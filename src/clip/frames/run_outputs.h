// The outputs of a run besides its pictures: --metrics (one row per output frame), --state
// (the final state, one row per particle, full precision), both written whole or not at
// all, and the metadata every PNG of a run carries.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "clip/common/cli_common.h"
#include "core/model/model.h"
#include "core/run/simulation.h"
#include "core/model/state.h"
#include "render/png_io.h"

namespace clothsim::clip {

// Columns: the contract's step,t,kinetic,spring_potential,gravity_potential,total_energy,
// max_strain,contacts,force_evals, then the implicit solver's newton_iterations,
// cg_iterations (cumulative), residual and converged (of the last step), then the run's
// scene,integrator,dt on every row, so a file says what made it (plot_energy.py labels by
// them), then step_size and rejected_steps (an adaptive pair's last step and refused trials).
// Columns rather than a header comment: CSV readers (csv.DictReader, pandas) read them without
// being told to skip comments, and added at the end, old readers are unchanged.
class MetricsWriter {
 public:
  MetricsWriter(const std::string& path, const Model& model, IntegratorKind kind, double dt);
  void row(const FrameMetrics& m);
  void commit() { file_.commit(); }
 private:
  AtomicFile file_;
  std::string run_columns_;  // ",scene,integrator,dt"
};

// The tEXt chunks of a run's PNGs: scene, source, integrator, dt, software (sinks add t).
PngText frame_metadata(const Model& model, IntegratorKind kind, double dt);

// The files a run has finished and the ones it writes after its frames (--summary, --state):
// a failure writing one of those (a full disk, ulimit -f) says what stays, as a signal does:
// "cannot write s.csv: File too large; kept m.csv, s.json; not written: s.csv".
class RunFiles {
 public:
  // `finished`: written by the pipeline; `after`: still to write, in order (empty paths skipped).
  RunFiles(const std::vector<std::string>& finished, const std::vector<std::string>& after);
  // Runs `write_file` for `path` (nothing when `path` is empty); on a RuntimeFailure rethrows
  // it with what stays appended.
  void write(const std::string& path, const std::function<void()>& write_file);
 private:
  std::vector<std::string> kept_, pending_;
};

// Header id,x,y,z,vx,vy,vz; %.17g, so a state read back is bit-identical.
void write_state_csv(const std::string& path, const Model& model, const State& state);

}  // namespace clothsim::clip
