#include "converge_outputs.h"

#include "clip/common/cli_common.h"
#include "clip/common/lanes.h"
#include "clip/common/summary_json.h"
#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"
#include "study/tables/csv_tables.h"

namespace clothsim::clip {

// The CSV (study/tables/csv_tables.h: the Python module's converge() has the same columns).
void write_converge_csv(std::FILE* f, const std::string& scene, const std::vector<ConvergencePoint>& points) {
  std::fputs(analysis::convergence_table(points, scene).text().c_str(), f);
}

// Per method and iteration count, the mean over the states of the RMS distance and the CPU,
// and how many of the states' steps read WRONG.
std::map<std::pair<int, int>, ConvergeMean> converge_means(const std::vector<ConvergencePoint>& points) {
  std::map<std::pair<int, int>, ConvergeMean> out;
  for (const ConvergencePoint& p : points) {
    ConvergeMean& m = out[{static_cast<int>(p.method), p.iterations}];
    m.rms += p.rms, m.cpu += p.cpu_seconds, ++m.n;
    if (!p.wrong.empty()) ++m.wrong;
  }
  for (auto& [key, m] : out) m.rms /= m.n, m.cpu /= m.n;
  return out;
}

void write_converge_summary(const std::string& path, const std::string& source, const ConvergenceSpec& spec,
                            const std::vector<ConvergencePoint>& points) {
  std::vector<JsonObject> lanes;
  for (const auto& [key, m] : converge_means(points))
    lanes.push_back(JsonObject()
                        .text("integrator", std::string(integrator_name(static_cast<IntegratorKind>(key.first))))
                        .number("dt", spec.h)
                        .integer("iterations", key.second)
                        .number("mean_rms_distance", m.rms)
                        .number("mean_cpu_seconds", m.cpu)
                        .integer("wrong_states", m.wrong));
  write_summary(path, "converge", source, lanes,
                JsonObject().integer("states", spec.states).integer("max_iterations", spec.max_iterations));
}

std::string converge_title(const Model& model, const ConvergenceSpec& spec) {
  return model.name + " (dt = " + step_string(spec.h) + " s)";
}

// --shard: this process's part of the sweeps, each journaled as it finishes (study_shard.h).
int converge_shard(const ConvergeOptions& o, const Model& model, const ConvergenceSpec& spec,
                   const analysis::StudyHooks& hooks) {
  ShardPlan plan{"converge", o.scene.path, o.scene.sets, "", converge_title(model, spec),
                 first_line(written_text([&](std::FILE* f) { write_converge_csv(f, model.name, {}); })), {}};
  for (double x : {spec.h, model.duration, double(spec.states), double(spec.max_iterations)})
    plan.plan += ";" + csv_number(x);
  for (const ConvergenceItem& item : convergence_items(spec)) {
    plan.plan += ";" + std::to_string(item.state) + " " + std::string(integrator_name(item.method));
    plan.costs.push_back(convergence_item_cost(spec, item));
  }
  StudyShard shard(o.shard, o.csv, o.plot, o.summary, plan);
  run_convergence_items(model, spec, shard.todo(), hooks, [&](std::size_t item, const std::vector<ConvergencePoint>& p) {
    shard.record(item, after_first_line(written_text([&](std::FILE* f) { write_converge_csv(f, model.name, p); })), "");
  });
  return shard.finish();
}

void write_converge_outputs(const ConvergeOptions& o, const std::string& source, const Model& model,
                            const ConvergenceSpec& spec, const std::vector<ConvergencePoint>& points, const PlotScript* plot) {
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    write_converge_csv(file.stream(), model.name, points);
    file.commit();
  };
  if (!o.csv.empty()) write_to(o.csv);
  if (!o.summary.empty()) write_converge_summary(o.summary, source, spec, points);
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", converge_title(model, spec)}, {o.csv, o.summary});
}

}  // namespace clothsim::clip
