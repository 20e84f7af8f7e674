#include "bench_outputs.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "clip/common/cli_common.h"
#include "clip/studies/study_shard.h"
#include "core/integrators/integrator_kind.h"
#include "study/reference.h"
#include "study/tables/csv_tables.h"
#include "study/work_precision_shard.h"

namespace clothsim::clip {
namespace {

using analysis::WorkPrecisionPoint;

// The reference's name in the summary: its integrator, or the adaptive pair.
std::string reference_name(const analysis::ReferenceCheck& ref) {
  return ref.adaptive ? "dopri5 (adaptive)" : std::string(integrator_name(ref.integrator));
}

// A shard's reference: saved in its directory, so a rerun measures against it without running it.
analysis::ShardReference shard_reference(const StudyShard& shard, const Model& model, const WorkPrecisionSpec& spec,
                                         const analysis::StudyHooks& hooks) {
  const std::string path = shard.dir() + "/reference";
  try {
    if (std::filesystem::exists(path)) return analysis::read_reference(analysis::read_whole_file(path));
    analysis::ShardReference ref = analysis::run_reference(model, spec, hooks);
    if (!ref.stopped) analysis::write_file_atomically(path, analysis::reference_text(ref, model.num_particles));
    return ref;
  } catch (const analysis::StudyError& e) {
    throw RuntimeFailure(path + ": " + e.what() + "; remove it to run the reference again");
  } catch (const std::runtime_error& e) {
    throw RuntimeFailure(e.what());
  }
}

}  // namespace

void write_bench_csv_header(std::FILE* f) { std::fputs(analysis::work_precision_table({}, {}).header().c_str(), f); }

void write_bench_csv_rows(std::FILE* f, const WorkPrecisionResult& r, const LaneNames& names) {
  const analysis::CsvTable t = analysis::work_precision_table(r, names);
  for (std::size_t i = 0; i < t.rows.size(); ++i) std::fputs(t.row_text(i).c_str(), f);
}

void write_bench_csv(std::FILE* f, const WorkPrecisionResult& r, const LaneNames& names) {
  write_bench_csv_header(f);
  write_bench_csv_rows(f, r, names);
}

JsonObject run_lane_json(const std::string& scene, const WorkPrecisionPoint& p, const LaneNames& names) {
  RunTotals t;
  t.steps = p.steps;
  t.force_evals = p.force_evals;
  t.newton_iterations = p.newton_iterations;
  t.cg_iterations = p.cg_iterations;
  t.unconverged_steps = p.unconverged_steps;
  t.cpu_seconds = p.cpu_seconds;
  JsonObject lane = lane_json(scene, p.integrator, p.dt, t, p.diverged ? std::optional<double>(p.diverged_at) : std::nullopt);
  lane.number("wall_seconds", p.wall_seconds)
      .number("rms_error", p.unresolved ? NAN : p.rms_error)
      .number("max_error", p.unresolved ? NAN : p.max_error)
      .boolean("unresolved", p.unresolved);
  if (p.tolerance > 0.0) lane.number("tolerance", p.tolerance).integer("rejected_steps", p.rejected_steps);
  lane.number("rms_error_at_end", p.unresolved ? NAN : p.rms_error_at_end)
      .number("rms_error_over_time", p.unresolved ? NAN : p.rms_error_over_time)
      .integer("samples", static_cast<std::int64_t>(p.samples));
  if (p.wrong) lane.number("wrong_at", p.wrong_at).text("wrong", p.wrong_reason);
  if (names[p.lane] != integrator_name(p.integrator)) lane.text("lane", names[p.lane]);
  return lane;
}

void write_bench_summary(const std::string& path, const std::string& source, const std::string& scene,
                         const WorkPrecisionResult& r, const LaneNames& names) {
  std::vector<JsonObject> lanes;
  for (const WorkPrecisionPoint& p : r.points) lanes.push_back(run_lane_json(scene, p, names));
  write_summary(path, "bench", source, lanes,
                bench_summary_keys(r.duration, r.complete, reference_name(r.reference), r.reference.dt,
                                   r.reference.finished ? r.reference.change_rms : NAN, r.reference.converged));
}

std::string bench_plot_title(const std::string& name, const WorkPrecisionResult& r) {
  // Three figures: a title is read, not parsed back (the CSV and the summary hold all 17; the
  // title printed "reference error 1.1274976125260227e-12 m RMS").
  const auto figures = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return std::string(text);
  };
  return name + " (T = " + figures(r.duration) + " s; reference error " +
         (r.reference.finished ? figures(r.reference.change_rms) : std::string("unknown")) + " m RMS)";
}

int bench_shard(const BenchOptions& o, const Model& model, const WorkPrecisionSpec& spec, const LaneNames& names,
                const analysis::StudyHooks& hooks) {
  WorkPrecisionResult row;  // one point at a time, with the study's T and reference
  row.duration = spec.duration;
  ShardPlan plan{"bench", o.scene.path, o.scene.sets, "", model.name + " (T = " + csv_number(spec.duration) + " s)",
                 first_line(written_text([&](std::FILE* f) { write_bench_csv(f, row, names); })), {}};
  for (const WorkPrecisionPoint& p : analysis::planned_points(spec)) {
    plan.plan += ";" + names[p.lane] + " " + csv_number(p.dt);  // the lane: its model is part of the item
    if (p.tolerance > 0.0) plan.plan += " tol " + csv_number(p.tolerance);
    plan.costs.push_back(analysis::point_cost(p, spec.duration));
  }
  plan.plan += ";T " + csv_number(spec.duration) + ";reference " + std::string(integrator_name(spec.reference_integrator)) +
               " /" + std::to_string(spec.reference_refinement);
  StudyShard shard(o.shard, o.csv, o.plot, o.summary, plan);
  if (shard.todo().empty()) return shard.finish();
  const analysis::ShardReference ref = shard_reference(shard, model, spec, hooks);
  row.reference.dt = ref.dt;
  row.reference.finished = ref.finished;
  row.reference.over_time = spec.error_over_time;
  row.reference.change_rms = spec.error_over_time ? ref.change_rms_over_time : ref.change_rms;
  row.reference.margin = spec.reference_margin;
  analysis::run_points(model, spec, ref, shard.todo(), hooks, [&](std::size_t item, WorkPrecisionPoint p) {
    if (ref.finished) p.unresolved = p.finished && p.rms_error * spec.reference_margin < row.reference.change_rms;
    row.points = {p};
    shard.record(item, after_first_line(written_text([&](std::FILE* f) { write_bench_csv(f, row, names); })),
                 run_lane_json(model.name, p, names).dump());
  });
  return shard.finish();
}

void write_bench_outputs(const BenchOptions& o, const std::string& source, const std::string& name,
                         const WorkPrecisionResult& r, const LaneNames& names, std::size_t runs, const PlotScript* plot) {
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    write_bench_csv(file.stream(), r, names);
    file.commit();
  };
  if (!o.csv.empty()) write_to(o.csv);
  if (!o.summary.empty()) write_bench_summary(o.summary, source, name, r, names);

  // Both files stay, each holding the runs that finished: the line names them.
  if (interrupted() || !r.complete)
    throw RuntimeFailure(study_interrupted_message(r.points.size(), runs, "runs", {o.csv, o.summary}, o.plot));
  if (!r.reference.converged) {
    std::string kept;
    for (const std::string& path : {o.csv, o.summary})
      if (!path.empty()) kept += (kept.empty() ? "" : ", ") + path;
    throw RuntimeFailure(source + ": " + r.reference.failure + (kept.empty() ? "" : " (kept for inspection: " + kept + ")") +
                         "; no plot drawn");
  }
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", bench_plot_title(name, r)}, {o.csv, o.summary});
}

analysis::CsvTable values_table(const std::vector<ValueStudy>& studies) {
  analysis::CsvTable table = analysis::work_precision_table({}, {});
  for (const ValueStudy& s : studies)
    for (std::vector<analysis::CsvCell>& row : analysis::work_precision_table(s.result, s.names).rows)
      table.rows.push_back(std::move(row));
  return table;
}

void write_values_outputs(const BenchOptions& o, const SceneDef& base, const std::vector<ValueStudy>& studies,
                          std::size_t done, std::size_t runs, const std::string& failure, const PlotScript* plot) {
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    write_bench_csv_header(file.stream());
    for (const ValueStudy& s : studies) write_bench_csv_rows(file.stream(), s.result, s.names);
    file.commit();
  };
  if (!o.csv.empty()) write_to(o.csv);
  if (interrupted() || !studies.back().result.complete)
    throw RuntimeFailure(study_interrupted_message(done, runs, "runs", {o.csv}, o.plot));
  if (!failure.empty())
    throw RuntimeFailure(base.source + ", " + failure + (o.csv.empty() ? "" : " (kept for inspection: " + o.csv + ")") +
                         "; no plot drawn");
  if (plot)
    plot->draw_from_csv(o.csv, write_to, {"--title", bench_plot_title(base.name, studies.front().result)}, {o.csv});
}

std::string scale_csv_text(const ScalePlan& plan, const std::vector<analysis::ScalePoint>& points) {
  std::string text = analysis::scale_csv_header() + "\n";
  for (const analysis::ScalePoint& p : points)
    text += analysis::scale_csv_row(p, plan.spec.lanes, plan.spec.duration) + "\n";
  return text;
}

void write_scale_outputs(const BenchOptions& o, const ScalePlan& plan, const std::vector<analysis::ScalePoint>& points,
                         const PlotScript* plot) {
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    std::fputs(scale_csv_text(plan, points).c_str(), file.stream());
    file.commit();
  };
  if (!o.csv.empty()) write_to(o.csv);
  if (interrupted())
    throw RuntimeFailure(study_interrupted_message(points.size(), plan.lanes->size() * plan.sides.size(), "runs",
                                                   {o.csv}, o.plot));
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", plan.spec.sizes.front().scene.name}, {o.csv});
}

}  // namespace clothsim::clip
