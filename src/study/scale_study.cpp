#include "scale_study.h"

#include <sys/resource.h>

#include <cmath>
#include <limits>

#include "io/csv_cells.h"
#include "parameter_sweep.h"
#include "study_run.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

// The process's peak resident set so far (Linux reports kilobytes).
double peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return 1024.0 * static_cast<double>(usage.ru_maxrss);
}

}  // namespace

double ScalePoint::newton_per_step() const {
  return totals.steps > 0 ? static_cast<double>(totals.newton_iterations) / totals.steps : 0.0;
}

double ScalePoint::linear_per_newton() const {
  return totals.newton_iterations > 0 ? static_cast<double>(totals.cg_iterations) / totals.newton_iterations : 0.0;
}

std::vector<ScaleScene> scale_scenes(const std::string& path, const std::vector<std::string>& sets,
                                     const std::vector<int>& sides) {
  if (sides.empty()) throw StudyError("no sizes given");
  for (std::size_t i = 0; i < sides.size(); ++i) {
    if (sides[i] < 2 || sides[i] > 2048) throw StudyError("size " + std::to_string(sides[i]) + " is not from 2 to 2048");
    if (i > 0 && sides[i] <= sides[i - 1]) throw StudyError("sizes must increase");
  }
  const double first_mass = load_scene(path, sets).cloth.particle_mass;
  std::vector<ScaleScene> out;
  for (int side : sides) {
    // (first / N)^2 keeps nx ny m, the sheet's total mass, as the first size has it.
    const double ratio = static_cast<double>(sides.front()) / side;
    std::vector<std::string> with = sets;
    with.push_back("cloth.particles=[" + std::to_string(side) + "," + std::to_string(side) + "]");
    with.push_back(set_text("cloth.particle_mass", first_mass * ratio * ratio));
    out.push_back({side, load_scene(path, with)});
  }
  return out;
}

std::vector<ScalePoint> scale_study(const ScaleSpec& spec, const StudyHooks& hooks,
                                    const std::function<void(const ScalePoint&)>& done) {
  std::vector<ScalePoint> points;
  const long total = static_cast<long>(spec.sizes.size() * spec.lanes.size());
  for (const ScaleScene& size : spec.sizes) {
    SceneDef scene = size.scene;
    scene.duration = std::max(scene.duration, spec.duration);
    const Model model = build_model(scene);
    for (std::size_t lane = 0; lane < spec.lanes.size(); ++lane) {
      if (hooks.stop && hooks.stop()) return points;
      const MethodSettings settings = spec.lane_settings ? spec.lane_settings(model, lane) : model.method_defaults();
      const ScaleLane& l = spec.lanes[lane];
      const StudyRun run = run_to(model, settings, l.kind, l.dt, spec.duration, hooks.stop);
      if (run.stopped) return points;
      ScalePoint p;
      p.lane = lane;
      p.side = size.side;
      p.particles = model.num_particles;
      p.particle_mass = scene.cloth.particle_mass;
      p.totals = run.totals;
      p.finished = run.finished;
      if (run.divergence) p.reason = run.divergence->reason;
      p.simulated = run.final_state.t;
      p.memory_estimate = model_bytes(scene) + run_bytes(scene, l.kind);
      p.peak_rss = peak_rss_bytes();
      points.push_back(p);
      if (done) done(p);
      if (hooks.progress) hooks.progress(StudyProgress{static_cast<long>(points.size()), total});
    }
  }
  return points;
}

double scale_exponent(const std::vector<ScalePoint>& points, std::size_t lane) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const ScalePoint& p : points) {
    if (p.lane != lane || !p.finished || !(p.cpu_per_simulated_second() > 0)) continue;
    const double x = std::log(static_cast<double>(p.particles)), y = std::log(p.cpu_per_simulated_second());
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double spread = n * sxx - sx * sx;
  if (n < 2 || !(spread > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (n * sxy - sx * sy) / spread;
}

std::string scale_csv_header() {
  return "lane,side,particles,particle_mass,dt,duration,simulated,steps,cpu_seconds,cpu_per_sim_second,"
         "newton_per_step,linear_per_newton,linear_per_step,factorizations,unconverged_steps,"
         "memory_estimate_mb,peak_rss_mb,finished,reason";
}

std::string scale_csv_row(const ScalePoint& p, const std::vector<ScaleLane>& lanes, double duration) {
  const double steps = static_cast<double>(p.totals.steps);
  const std::string cells[] = {
      csv_text(lanes[p.lane].name), std::to_string(p.side), std::to_string(p.particles), csv_number(p.particle_mass),
      csv_number(lanes[p.lane].dt), csv_number(duration), csv_number(p.simulated), std::to_string(p.totals.steps),
      csv_number(p.totals.cpu_seconds), csv_number(p.cpu_per_simulated_second()), csv_number(p.newton_per_step()),
      csv_number(p.linear_per_newton()), csv_number(steps > 0 ? p.totals.cg_iterations / steps : 0.0),
      std::to_string(p.totals.factorizations), std::to_string(p.totals.unconverged_steps),
      csv_number(p.memory_estimate / (1 << 20)), csv_number(p.peak_rss / (1 << 20)), p.finished ? "1" : "0",
      csv_text(p.reason)};
  std::string row;
  for (const std::string& c : cells) row += (row.empty() ? "" : ",") + c;
  return row;
}

}  // namespace clothsim::analysis
