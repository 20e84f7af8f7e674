// The outputs of a run besides its pictures: --metrics (one row per output frame), --state
// (the final state, one row per particle, full precision), both written whole or not at
// all, and the metadata every PNG of a run carries.
#pragma once

#include <string>

#include "cli_common.h"
#include "model.h"
#include "png_io.h"
#include "simulation.h"
#include "state.h"

namespace clothsim::cli {

// Columns: the contract's step,t,kinetic,spring_potential,gravity_potential,total_energy,
// max_strain,contacts,force_evals, then the implicit solver's newton_iterations,
// cg_iterations (cumulative), residual and converged (of the last step).
class MetricsWriter {
 public:
  explicit MetricsWriter(const std::string& path);
  void row(const FrameMetrics& m);
  void commit() { file_.commit(); }
 private:
  AtomicFile file_;
};

// The tEXt chunks of a run's PNGs: scene, source, integrator, dt, software (sinks add t).
PngText frame_metadata(const Model& model, IntegratorKind kind, double dt);

// Header id,x,y,z,vx,vy,vz; %.17g, so a state read back is bit-identical.
void write_state_csv(const std::string& path, const Model& model, const State& state);

}  // namespace clothsim::cli
