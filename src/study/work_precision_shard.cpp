#include "work_precision_shard.h"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <sstream>

#include "task_pool.h"

namespace clothsim::analysis {

ShardReference run_reference(const Model& model, const WorkPrecisionSpec& spec_in, const StudyHooks& hooks) {
  const WorkPrecisionSpec spec = checked(spec_in);
  const double h_coarse = spec.dts.front() / spec.reference_refinement;
  StudyRun runs[2];
  parallel_for(2, std::min(spec.jobs <= 0 ? 2 : spec.jobs, 2), [&](std::size_t i) {
    runs[i] = reference_run(model, spec, i == 1, hooks.stop);
  }, hooks.stop);
  ShardReference ref;
  ref.dt = uses_adaptive_reference(model, spec) ? 0.0 : 0.5 * h_coarse;
  ref.stopped = runs[0].stopped || runs[1].stopped || (hooks.stop && hooks.stop());
  ref.finished = runs[0].finished && runs[1].finished;
  ref.fine_finished = runs[1].finished;
  ref.fine = std::move(runs[1].final_state);
  if (ref.finished) {
    const PositionError change = position_error(model, runs[0].final_state.x, ref.fine.x, ref.fine.inv_mass);
    ref.change_rms = change.rms;
    ref.change_max = change.max;
  }
  return ref;
}

std::string reference_text(const ShardReference& ref, int particles) {
  std::ostringstream out;
  char line[200];
  std::snprintf(line, sizeof line, "%d %d %a %a %a %d\n", ref.finished ? 1 : 0, ref.fine_finished ? 1 : 0, ref.dt,
                ref.change_rms, ref.change_max, ref.fine_finished ? particles : 0);
  out << line;
  for (int p = 0; ref.fine_finished && p < particles; ++p) {
    std::snprintf(line, sizeof line, "%a %a %a %a\n", ref.fine.x(0, p), ref.fine.x(1, p), ref.fine.x(2, p),
                  ref.fine.inv_mass[p]);
    out << line;
  }
  return out.str();
}

ShardReference read_reference(const std::string& text) {
  ShardReference ref;
  std::istringstream in(text);
  int finished = 0, fine_finished = 0, particles = 0;
  std::string dt, rms, max;
  if (!(in >> finished >> fine_finished >> dt >> rms >> max >> particles) || particles < 0)
    throw StudyError("the saved reference is not one");
  ref.finished = finished == 1;
  ref.fine_finished = fine_finished == 1;
  ref.dt = std::strtod(dt.c_str(), nullptr);
  ref.change_rms = std::strtod(rms.c_str(), nullptr);
  ref.change_max = std::strtod(max.c_str(), nullptr);
  ref.fine.x.resize(3, particles);
  ref.fine.inv_mass.resize(particles);
  for (int p = 0; p < particles; ++p) {
    std::string v[4];
    if (!(in >> v[0] >> v[1] >> v[2] >> v[3])) throw StudyError("the saved reference is cut short");
    for (int r = 0; r < 3; ++r) ref.fine.x(r, p) = std::strtod(v[r].c_str(), nullptr);
    ref.fine.inv_mass[p] = std::strtod(v[3].c_str(), nullptr);
  }
  return ref;
}

std::vector<WorkPrecisionPoint> run_points(const Model& model, const WorkPrecisionSpec& spec_in,
                                           const ShardReference& ref, const std::vector<std::size_t>& items,
                                           const StudyHooks& hooks,
                                           const std::function<void(std::size_t, const WorkPrecisionPoint&)>& finished) {
  const WorkPrecisionSpec spec = checked(spec_in);
  const std::vector<WorkPrecisionPoint> planned = planned_points(spec);
  std::vector<std::size_t> order = items;  // dearest first, as the single-process pool does
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return cost_estimate(planned[a].integrator, spec.duration, planned[a].dt) >
           cost_estimate(planned[b].integrator, spec.duration, planned[b].dt);
  });
  std::vector<WorkPrecisionPoint> points(planned.size());
  std::vector<bool> ran(planned.size(), false);
  std::mutex mutex;
  const auto cost = [&](std::size_t item) { return cost_estimate(planned[item].integrator, spec.duration, planned[item].dt); };
  StudyProgress progress{0, static_cast<long>(order.size())};  // weighed as work_precision's
  for (std::size_t item : order) progress.work_total += cost(item);
  parallel_for(order.size(), spec.jobs, [&](std::size_t i) {
    const std::size_t item = order[i];
    const StudyRun run = run_to(model, lane_settings(spec, planned[item].lane, model), planned[item].integrator,
                                planned[item].dt, spec.duration, hooks.stop);
    if (run.stopped) return;
    const WorkPrecisionPoint p = measured_point(planned[item], run, model, ref.fine_finished ? &ref.fine : nullptr);
    std::lock_guard<std::mutex> lock(mutex);
    if (finished) finished(item, p);
    points[item] = p;
    ran[item] = true;
    ++progress.done;
    progress.work_done += cost(item);
    if (hooks.progress) hooks.progress(progress);
  }, hooks.stop);
  std::vector<WorkPrecisionPoint> kept;
  for (std::size_t k = 0; k < planned.size(); ++k)
    if (ran[k]) kept.push_back(points[k]);
  return kept;
}

}  // namespace clothsim::analysis
