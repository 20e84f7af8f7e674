#include "work_precision_shard.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <sstream>

#include "task_pool.h"

namespace clothsim::analysis {

ShardReference run_reference(const Model& model, const WorkPrecisionSpec& spec_in, const StudyHooks& hooks) {
  const WorkPrecisionSpec spec = checked(spec_in);
  const double h_coarse = spec.dts.front() / spec.reference_refinement;
  const std::vector<double> times = sample_times(spec);
  StudyRun runs[2];
  std::vector<ReferenceSample> samples[2];  // the coarser's and the finer's, at every time reached
  parallel_for(2, std::min(spec.jobs <= 0 ? 2 : spec.jobs, 2), [&](std::size_t i) {
    Sampling sampling{times, [&, i](std::size_t, const State& s) {
                        samples[i].push_back({s.x.leftCols(model.num_particles), s.inv_mass.head(model.num_particles)});
                      }};
    runs[i] = reference_run(model, spec, i == 1, hooks.stop, sampling);
  }, hooks.stop);
  ShardReference ref;
  ref.dt = uses_adaptive_reference(model, spec) ? 0.0 : 0.5 * h_coarse;
  ref.stopped = runs[0].stopped || runs[1].stopped || (hooks.stop && hooks.stop());
  ref.finished = runs[0].finished && runs[1].finished;
  ref.coarse_finished = runs[0].finished;
  ref.fine_finished = runs[1].finished;
  ref.fine = std::move(runs[1].final_state);
  ref.coarse_totals = runs[0].totals;
  ref.fine_totals = runs[1].totals;
  ref.coarse_divergence = runs[0].divergence;
  ref.fine_divergence = runs[1].divergence;
  ref.samples = std::move(samples[1]);
  if (ref.finished) {
    const PositionError change = position_error(model, runs[0].final_state.x, ref.fine.x, ref.fine.inv_mass);
    ref.change_rms = change.rms;
    ref.change_max = change.max;
    for (std::size_t k = 0; k < ref.samples.size() && k < samples[0].size(); ++k) {
      const PositionError at = position_error(model, samples[0][k].x, ref.samples[k].x, ref.samples[k].free);
      ref.change_rms_over_time = std::max(ref.change_rms_over_time, at.rms);
      ref.change_max_over_time = std::max(ref.change_max_over_time, at.max);
    }
  }
  return ref;
}

namespace {

void write_cloth(std::ostringstream& out, const Eigen::Matrix3Xd& x, const Eigen::VectorXd& free, int particles) {
  char line[200];
  for (int p = 0; p < particles; ++p) {
    std::snprintf(line, sizeof line, "%a %a %a %a\n", x(0, p), x(1, p), x(2, p), free[p]);
    out << line;
  }
}

void read_cloth(std::istringstream& in, Eigen::Matrix3Xd& x, Eigen::VectorXd& free, int particles) {
  x.resize(3, particles);
  free.resize(particles);
  for (int p = 0; p < particles; ++p) {
    std::string v[4];
    if (!(in >> v[0] >> v[1] >> v[2] >> v[3])) throw StudyError("the saved reference is cut short");
    for (int r = 0; r < 3; ++r) x(r, p) = std::strtod(v[r].c_str(), nullptr);
    free[p] = std::strtod(v[3].c_str(), nullptr);
  }
}

}  // namespace

std::string reference_text(const ShardReference& ref, int particles) {
  std::ostringstream out;
  char line[300];
  std::snprintf(line, sizeof line, "%d %d %a %a %a %a %a %d %zu\n", ref.finished ? 1 : 0, ref.fine_finished ? 1 : 0,
                ref.dt, ref.change_rms, ref.change_max, ref.change_rms_over_time, ref.change_max_over_time,
                ref.fine_finished ? particles : 0, ref.fine_finished ? ref.samples.size() : 0);
  out << line;
  if (!ref.fine_finished) return out.str();
  write_cloth(out, ref.fine.x, ref.fine.inv_mass, particles);
  for (const ReferenceSample& s : ref.samples) write_cloth(out, s.x, s.free, particles);
  return out.str();
}

ShardReference read_reference(const std::string& text) {
  ShardReference ref;
  std::istringstream in(text);
  int finished = 0, fine_finished = 0, particles = 0;
  long samples = 0;
  std::string dt, rms, max, rms_t, max_t;
  if (!(in >> finished >> fine_finished >> dt >> rms >> max >> rms_t >> max_t >> particles >> samples) ||
      particles < 0 || samples < 0 || samples > kMaxSamples)
    throw StudyError("the saved reference is not one");
  ref.finished = finished == 1;
  ref.coarse_finished = ref.finished;
  ref.fine_finished = fine_finished == 1;
  ref.dt = std::strtod(dt.c_str(), nullptr);
  ref.change_rms = std::strtod(rms.c_str(), nullptr);
  ref.change_max = std::strtod(max.c_str(), nullptr);
  ref.change_rms_over_time = std::strtod(rms_t.c_str(), nullptr);
  ref.change_max_over_time = std::strtod(max_t.c_str(), nullptr);
  read_cloth(in, ref.fine.x, ref.fine.inv_mass, particles);
  ref.samples.resize(static_cast<std::size_t>(samples));
  for (ReferenceSample& s : ref.samples) read_cloth(in, s.x, s.free, particles);
  return ref;
}

std::vector<WorkPrecisionPoint> run_points(const Model& model, const WorkPrecisionSpec& spec_in,
                                           const ShardReference& ref, const std::vector<std::size_t>& items,
                                           const StudyHooks& hooks,
                                           const std::function<void(std::size_t, const WorkPrecisionPoint&)>& finished) {
  const WorkPrecisionSpec spec = checked(spec_in);
  const std::vector<WorkPrecisionPoint> planned = planned_points(spec);
  const std::vector<double> times = sample_times(spec);
  std::vector<std::size_t> order = items;  // dearest first, as the single-process pool does
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return point_cost(planned[a], spec.duration) > point_cost(planned[b], spec.duration);
  });
  std::vector<WorkPrecisionPoint> points(planned.size());
  std::vector<bool> ran(planned.size(), false);
  std::mutex mutex;
  const auto cost = [&](std::size_t item) { return point_cost(planned[item], spec.duration); };
  StudyProgress progress{0, static_cast<long>(order.size())};  // weighed as work_precision's
  for (std::size_t item : order) progress.work_total += cost(item);
  parallel_for(order.size(), spec.jobs, [&](std::size_t i) {
    const std::size_t item = order[i];
    // The error over time, measured as the run passes each sample time the reference reached.
    PositionError worst;
    int measured = 0;
    const Sampling sampling{times, [&](std::size_t k, const State& s) {
                              if (k >= ref.samples.size()) return;
                              const PositionError e = position_error(model, s.x, ref.samples[k].x, ref.samples[k].free);
                              worst.rms = std::max(worst.rms, e.rms), worst.max = std::max(worst.max, e.max);
                              ++measured;
                            }};
    const StudyRun run = run_point(model, spec, planned[item], hooks.stop, sampling);
    if (run.stopped) return;
    WorkPrecisionPoint p = measured_point(planned[item], run, model, ref.fine_finished ? &ref.fine : nullptr);
    if (p.finished && ref.fine_finished) {
      p.rms_error_over_time = worst.rms, p.max_error_over_time = worst.max;
      p.samples = measured;
    }
    judge_error(p, spec.error_over_time);
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
