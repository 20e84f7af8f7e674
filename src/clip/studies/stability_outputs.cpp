#include "stability_outputs.h"

#include <cmath>

#include "clip/common/cli_common.h"
#include "clip/studies/study_shard.h"
#include "core/integrators/integrator_kind.h"
#include "study/tables/csv_tables.h"

namespace clothsim::clip {

using analysis::StabilityLimit;

void write_stability_csv(std::FILE* f, const std::string& param, const std::vector<StabilityLimit>& limits,
                         const analysis::StabilitySpec& spec, const LaneNames& names) {
  std::fputs(analysis::stability_table(limits, spec, param, names).text().c_str(), f);
}

JsonObject search_lane_json(const std::string& scene, const StabilityLimit& l, const LaneNames& names) {
  std::vector<JsonObject> frame_steps;
  for (const analysis::FrameStepResult& f : l.frame_steps) {
    JsonObject step;
    step.number("dt", f.dt)
        .integer("steps", f.steps)
        .integer("unconverged_steps", f.unconverged_steps)
        .number("diverged_at", f.failure == analysis::Failure::Diverged ? std::optional<double>(f.diverged_at)
                                                                        : std::nullopt)
        .text("failure", analysis::failure_name(f.failure));
    frame_steps.push_back(step);
  }
  JsonObject lane = lane_json_without_counts(scene, l.integrator,
                                             std::isfinite(l.stable_dt) ? std::optional<double>(l.stable_dt) : std::nullopt,
                                             l.cpu_seconds);
  lane.number("value", l.value)
      .text("outcome", analysis::outcome_name(l.outcome))
      .number("stable_dt", l.stable_dt)
      .number("unstable_dt", l.unstable_dt)
      .text("failure", analysis::failure_name(l.failure))
      .text("reason", l.reason)
      .integer("trials", l.trials)
      .number("w_max", l.estimate.w_max)
      .number("dt_springs", l.estimate.dt_springs())
      .number("dt_with_damping", l.estimate.dt_with_damping())
      .array("frame_steps", frame_steps);
  if (names[l.lane] != integrator_name(l.integrator)) lane.text("lane", names[l.lane]);
  return lane;
}

void write_stability_summary(const std::string& path, const std::string& source, const std::string& scene,
                             const std::string& param, const std::vector<StabilityLimit>& limits,
                             const analysis::StabilitySpec& spec, const LaneNames& names, bool complete) {
  std::vector<JsonObject> lanes;
  for (const StabilityLimit& l : limits) lanes.push_back(search_lane_json(scene, l, names));
  JsonObject extra;
  extra.text("param", param)
      .number("duration", spec.duration)
      .number("min_dt", spec.min_dt)
      .number("max_dt", spec.max_dt)
      .boolean("complete", complete);
  write_summary(path, "stability", source, lanes, extra);
}

int stability_shard(const StabilityOptions& o, const std::string& title, const std::vector<analysis::StabilityCase>& refs,
                    const analysis::StabilitySpec& spec, const LaneNames& names, const analysis::StudyHooks& hooks) {
  ShardPlan plan{"stability", o.scene.path, o.scene.sets, o.param, title,
                 first_line(written_text([&](std::FILE* f) { write_stability_csv(f, o.param, {}, spec, names); })), {}};
  for (const analysis::StabilityCase& c : refs)
    for (std::size_t lane = 0; lane < spec.integrators.size(); ++lane) {  // the lane: its settings are part of the item
      plan.plan += ";" + csv_number(c.value) + " " + names[lane];
      plan.costs.push_back(
          analysis::search_cost(*c.model, analysis::case_lane_settings(c, lane), spec.integrators[lane], spec));
    }
  for (double x : {spec.duration, spec.min_dt, spec.max_dt, spec.precision, spec.energy_factor, spec.max_strain})
    plan.plan += ";" + csv_number(x);
  for (double dt : spec.frame_dts) plan.plan += ";frame " + csv_number(dt);
  StudyShard shard(o.shard, o.csv, o.plot, o.summary, plan);
  analysis::stability_sweep_items(refs, spec, shard.todo(), hooks, [&](std::size_t item, const StabilityLimit& l) {
    shard.record(item, after_first_line(written_text([&](std::FILE* f) { write_stability_csv(f, o.param, {l}, spec, names); })),
                 search_lane_json(title, l, names).dump());
  });
  return shard.finish();
}

void write_stability_outputs(const StabilityOptions& o, const SceneDef& base, const std::vector<StabilityLimit>& limits,
                             const StabilityStudy& study, const PlotScript* plot) {
  const analysis::StabilitySpec& spec = study.spec;
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    write_stability_csv(file.stream(), o.param, limits, spec, study.names);
    file.commit();
  };
  if (!o.csv.empty()) write_to(o.csv);
  const std::size_t searches = study.cases.size() * spec.integrators.size();
  if (!o.summary.empty())
    write_stability_summary(o.summary, base.source, base.name, o.param, limits, spec, study.names,
                            limits.size() == searches);
  // Both files stay, each holding the searches that finished: the line names them.
  if (interrupted() || limits.size() < searches)
    throw RuntimeFailure(study_interrupted_message(limits.size(), searches, "searches", {o.csv, o.summary}, o.plot));
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", base.name}, {o.csv, o.summary});  // the script adds T from the CSV
}

}  // namespace clothsim::clip
