#include "compare_summary.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "core/run/work_units.h"
#include "render/video/tiling.h"
#include "render/video/video_writer.h"
#include "study/reference.h"

namespace clothsim::clip {

namespace {

// Cost per simulated second over the time actually simulated (up to divergence).
double simulated(const LaneResult& r) { return r.divergence ? r.divergence->t : r.t; }

// The name column's width: 30, or the longest name (--vary's "rk4, collision.model = barrier").
int name_width(const std::vector<std::string>& names) {
  std::size_t width = 30;
  for (const std::string& n : names) width = std::max(width, n.size());
  return static_cast<int>(width);
}

void print_row(const LaneResult& r, const std::string& name, const std::string& wrong, int width) {
  const double t = simulated(r);
  // An adaptive pair's dt_s is the mean of the steps it chose, not its first trial.
  const bool adaptive = integrator_info(r.spec.kind).adaptive && r.totals.steps > 0;
  const double dt = adaptive ? t / static_cast<double>(r.totals.steps) : r.spec.dt;
  std::printf("%-*s %10.3g %10" PRId64 " %13" PRId64 " %12.3g %9.3f %14.1f  %s\n", width, name.c_str(), dt,
              r.totals.steps, r.totals.force_evals, t > 0 ? spring_passes(r.totals) / t : 0.0, r.totals.cpu_seconds,
              t > 0 ? 1e3 * r.totals.cpu_seconds / t : 0.0, lane_result(r, wrong).c_str());
}

// Which frames a lane's field numbers cover, and why a lane that diverged (or whose reference
// did) was measured only up to then: else "largest 0 m" would read as a perfect lane.
std::string measured_note(const PipelineReport& report, std::size_t i, FieldKind color) {
  const LaneResult& r = report.lanes[i].result;
  std::string measured = " (never measured";  // never: no number to quote, the note says why
  if (report.lanes[i].field_count > 0) {
    char text[160];
    // A lane whose step is longer than the frame interval stands on one state for several
    // frames: how many states those frames showed, where it is fewer.
    const long frames = report.lanes[i].field_count, states = report.lanes[i].field_states;
    char distinct[64] = "";
    if (states < frames)
      std::snprintf(distinct, sizeof distinct, " (%ld distinct state%s of the lane)", states, states == 1 ? "" : "s");
    if (frames == 1)
      std::snprintf(text, sizeof text, " (measured at 1 frame, t = %.4g s", report.lanes[i].field_last_t);
    else
      std::snprintf(text, sizeof text, " (measured at %ld frames%s, t = %.4g to %.4g s", frames, distinct,
                    report.lanes[i].field_first_t, report.lanes[i].field_last_t);
    measured = text;
  }
  const LaneResult* reference = lane_reference(report, i);
  const bool reference_diverged = color == FieldKind::Error && reference && reference->divergence;
  char why[80] = "";
  if (r.divergence)
    std::snprintf(why, sizeof why, "; it diverged at t = %.6g s", r.divergence->t);
  else if (reference_diverged)
    std::snprintf(why, sizeof why, "; the reference diverged at t = %.6g s", reference->divergence->t);
  return measured + why + ")";
}

// What a reference row is called: "(reference)", or under --vary "(reference, VALUE)".
std::string reference_role(const ReferenceReport& ref) {
  return ref.label.empty() ? "(reference)" : "(reference, " + ref.label + ")";
}

// The reference's row: its method, and for the adaptive one its tolerance in the step's column.
std::string reference_row_name(const ReferenceReport& ref) {
  return (ref.result.adaptive_tolerance > 0.0 ? std::string("dopri5 adaptive") : ref.result.spec.name()) + " " +
         reference_role(ref);
}

void print_reference_row(const ReferenceReport& ref, int width) {
  const LaneResult& r = ref.result;
  if (!(r.adaptive_tolerance > 0.0)) return print_row(r, reference_row_name(ref), "", width);
  const double t = simulated(r);
  char tolerance[32];
  std::snprintf(tolerance, sizeof tolerance, "tol %.0e", r.adaptive_tolerance);
  std::printf("%-*s %10s %10" PRId64 " %13" PRId64 " %12.3g %9.3f %14.1f  %s\n", width, reference_row_name(ref).c_str(),
              tolerance, r.totals.steps, r.totals.force_evals, t > 0 ? spring_passes(r.totals) / t : 0.0,
              r.totals.cpu_seconds, t > 0 ? 1e3 * r.totals.cpu_seconds / t : 0.0, lane_result(r, "").c_str());
}

// A reference's line under the error numbers: what it is, its estimated error, and how far
// below the smallest error of the lanes it measures that lies.
void print_reference_error(const PipelineReport& report, std::size_t k) {
  const LaneResult& ref = report.references[k].result;
  const std::string& label = report.references[k].label;
  const std::string head = label.empty() ? "reference" : "reference for " + label;
  const bool adaptive = ref.adaptive_tolerance > 0.0;
  if (std::isnan(ref.estimated_error)) {
    std::printf("%s: %s @ %s s, fixed step; its own error is not estimated: %s (docs/integrators.md)\n", head.c_str(),
                ref.spec.name().c_str(), ref.spec.step_text.c_str(),
                ref.check_dt > 0.0 ? "the check at twice its step did not finish" : "no check ran");
    return;
  }
  // The smallest error quoted: a diverged lane's is not (its line says so), nor is an
  // unresolved one's, which is the reference's own.
  double smallest = NAN;
  for (std::size_t i = 0; i < report.lanes.size(); ++i)
    if (report.lanes[i].reference == static_cast<int>(k) && report.lanes[i].field_count > 0 &&
        report.lanes[i].field_max > 0.0 && !report.lanes[i].result.divergence &&
        !lane_unresolved(report, i, FieldKind::Error) && !(smallest <= report.lanes[i].field_max))
      smallest = report.lanes[i].field_max;  // (a lane measured only at t = 0, where all agree, has none)
  std::printf("%s: ", head.c_str());
  if (adaptive)
    std::printf("dopri5 adaptive at tolerance %.0e, checked by a solve at %.0e",
                ref.adaptive_tolerance, ref.check_tolerance);
  else
    std::printf("%s @ %s s, checked by a run at twice its step (%.3g s)", ref.spec.name().c_str(),
                ref.spec.step_text.c_str(), ref.check_dt);
  std::printf(": estimated error %.3g m, the largest over the measured frames", ref.estimated_error);
  if (!std::isnan(smallest) && ref.estimated_error > 0.0)
    std::printf(" (%.2g %% of the smallest lane error, %.3g m)", 100.0 * ref.estimated_error / smallest, smallest);
  std::printf("\n");
  if (!ref.cache.empty()) std::printf("%s: %s\n", head.c_str(), reference_cache_text(ref).c_str());
}

// The colouring in numbers: how far each lane strayed from the reference (or how strained,
// how fast), the largest over the clip and at its end. An error under 10x the reference's own
// is unresolved: no number is given for it.
void print_fields(const PipelineReport& report, FieldKind color, const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < report.lanes.size(); ++i) {
    const LaneResult& r = report.lanes[i].result;
    const LaneResult* reference = lane_reference(report, i);
    std::string values;
    if (r.divergence && color == FieldKind::Error && report.lanes[i].field_count > 0) {
      // Its error before the blow-up is no result: said as diverged, never unresolved.
      char text[160];
      std::snprintf(text, sizeof text, " diverged at t = %.4g s (step %ld), so no error is quoted", r.divergence->t,
                    static_cast<long>(r.divergence->step));
      values = text;
    } else if (report.lanes[i].field_count > 0 && lane_unresolved(report, i, color)) {
      char text[160];
      std::snprintf(text, sizeof text, " unresolved: under %g x the reference's estimated error (%.3g m)",
                    kUnresolvedFactor, reference->estimated_error);
      values = text;
    } else if (report.lanes[i].field_count > 0) {
      char text[160];
      std::snprintf(text, sizeof text, " largest %.3g%s, at the end %.3g%s", report.lanes[i].field_max,
                    field_unit(color).c_str(), report.lanes[i].field_last, field_unit(color).c_str());
      values = text;
    }
    const std::string against = color != FieldKind::Error || !reference ? ":"
                                : reference->adaptive_tolerance > 0.0
                                    ? " against the adaptive reference:"
                                    : " against " + reference->spec.name() + " @ " + reference->spec.step_text + " s:";
    std::printf("%s @ %s s: %s%s%s%s\n", names[i].c_str(), r.spec.step_text.c_str(),
                std::string(field_kind_name(color)).c_str(), against.c_str(), values.c_str(),
                measured_note(report, i, color).c_str());
  }
}

// What the implicit solve did, beside the table (0 for the explicit family, so not a column):
// contacts it held as constraints, and particles the post-step projection still had to move.
void print_solver_work(const PipelineReport& report, const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < report.lanes.size(); ++i) {
    const LaneResult& r = report.lanes[i].result;
    if (r.spec.fixed_point)  // the course's one-iteration fixed point: no Newton, no CG, no contacts held
      std::printf("%s @ %s s: %" PRId64 " fixed-point iterations; post-step projections %" PRId64 " on %" PRId64
                  " of %" PRId64 " steps, largest strain %.3g\n",
                  names[i].c_str(), r.spec.step_text.c_str(), r.totals.newton_iterations,
                  r.totals.safety_projections, r.totals.projected_steps, r.totals.steps, r.totals.max_strain);
    else if (integrator_info(r.spec.kind).iterations == IterationControl::Newton)
      std::printf("%s @ %s s: %" PRId64 " Newton and %" PRId64 " CG iterations (%" PRId64 " assemblies, %" PRId64
                  " sparse factorizations), largest final residual %.2g; "
                  "contacts held in the solve %" PRId64 ", post-step projections %" PRId64 "\n",
                  names[i].c_str(), r.spec.step_text.c_str(), r.totals.newton_iterations, r.totals.cg_iterations,
                  r.totals.assemblies, r.totals.factorizations, r.totals.max_residual, r.totals.contact_constraints,
                  r.totals.safety_projections);
  }
}

JsonObject lane_summary(const Model& model, const LaneResult& r, const std::string& role) {
  const double t = simulated(r);
  // The adaptive reference runs the dopri5 solve in place of its lane (lane_worker.h): its row
  // says so, with no step, its tolerances beside it.
  const bool adaptive_reference = r.adaptive_tolerance > 0.0;
  JsonObject lane = lane_json(model.name, adaptive_reference ? kAdaptiveReferenceIntegrator : r.spec.kind,
                              adaptive_reference ? std::nan("") : r.spec.dt, r.totals,
                              r.divergence ? std::optional<double>(r.divergence->t) : std::nullopt)
                        .number("t_reached", r.t)
                        .number("spring_passes", spring_passes(r.totals))
                        // The adaptive solve's strain is not measured: null, not 0.
                        .number("max_strain", adaptive_reference ? std::nan("") : r.totals.max_strain)
                        .number("projected_steps", static_cast<double>(r.totals.projected_steps))
                        .number("spring_passes_per_s", t > 0 ? spring_passes(r.totals) / t : std::nan(""))
                        .text("lane", r.adaptive_tolerance > 0.0 ? std::string("dopri5 (adaptive)") : r.spec.spelling())
                        .text("role", role);
  if (adaptive_reference)
    lane.number("tolerance", r.adaptive_tolerance).number("check_tolerance", r.check_tolerance);
  if (!r.cache.empty()) lane.text("cache", r.cache);
  if (integrator_info(r.spec.kind).adaptive && !adaptive_reference)  // an adaptive pair's own steps and error control
    lane.number("rejected_steps", static_cast<double>(r.totals.rejected_steps))
        .number("smallest_step", r.totals.smallest_step)
        .number("largest_step", r.totals.largest_step)
        .number("rtol", r.spec.rtol > 0.0 ? r.spec.rtol : model.adaptive.rtol)  // the lane's, else the scene's
        .number("atol", r.spec.atol > 0.0 ? r.spec.atol : model.adaptive.atol);
  return lane;
}

// A lane's colouring field in numbers (NaN, written null, when it was never coloured).
JsonObject& with_field(JsonObject& lane, const PipelineReport& report, std::size_t i) {
  return lane.number("field_max", report.lanes[i].field_max)
      .number("field_last", report.lanes[i].field_last)
      .number("field_frames", static_cast<double>(report.lanes[i].field_count))
      .number("field_states", static_cast<double>(report.lanes[i].field_states))
      .number("field_first_t", report.lanes[i].field_first_t)
      .number("field_last_t", report.lanes[i].field_last_t);
}

}  // namespace

// Whether the reference was computed or served from the cache (LaneResult::cache).
std::string reference_cache_text(const LaneResult& ref) {
  char text[512];
  if (ref.cache == "reused")
    std::snprintf(text, sizeof text, "reused from the cache (%s), computed there in %.3g s of CPU, read here in %.3g s",
                  ref.cache_file.c_str(), ref.computed_cpu_seconds, ref.totals.cpu_seconds);
  else if (ref.cache == "stored")
    std::snprintf(text, sizeof text, "computed, and stored in the cache (%s)", ref.cache_file.c_str());
  else if (ref.cache == "off")
    std::snprintf(text, sizeof text, "computed (the cache is off: --no-reference-cache, or CLOTHSIM_REFERENCE_CACHE_MAX=0)");
  else if (ref.cache == "not cached")
    std::snprintf(text, sizeof text, "computed (a reference of this method reads settings the cache's key leaves out)");
  else
    std::snprintf(text, sizeof text, "computed, %s", ref.cache.c_str());
  return text;
}

std::string lane_result(const LaneResult& r, const std::string& wrong) {
  char result[192];
  if (r.divergence)
    std::snprintf(result, sizeof result, "DIVERGED at t = %.6g s (step %" PRId64 "): %s", r.divergence->t,
                  r.divergence->step, r.divergence->reason.c_str());
  else if (r.totals.unconverged_steps > 0 && r.spec.newton_capped())
    std::snprintf(result, sizeof result, "ok to t = %.4g s (Newton capped at %d: residual up to %.2g)", r.t,
                  r.spec.iterations, r.totals.max_residual);
  else if (r.totals.unconverged_steps > 0)
    std::snprintf(result, sizeof result,
                  "NOT CONVERGED: %" PRId64 " of %" PRId64 " steps, max residual %.2g (to t = %.4g s)",
                  r.totals.unconverged_steps, r.totals.steps, r.totals.max_residual, r.t);
  else if (!wrong.empty())
    std::snprintf(result, sizeof result, "%s (to t = %.4g s)", wrong.c_str(), r.t);
  else
    std::snprintf(result, sizeof result, "ok to t = %.4g s", r.t);
  return result;
}

void print_summary(const Model& model, const PipelineReport& report, FieldKind color, const SummaryContext& context) {
  std::printf("%s: %zu lanes\n", model.name.c_str(), report.lanes.size());
  std::vector<std::string> names = context.names;
  for (const ReferenceReport& ref : report.references) names.push_back(reference_row_name(ref));
  const int width = name_width(names);
  std::printf("%-*s %10s %10s %13s %12s %9s %14s  %s\n", width, "lane", "dt_s", "steps", "force_evals", "passes_per_s",
              "cpu_s", "cpu_ms_per_s", "result");
  for (std::size_t i = 0; i < report.lanes.size(); ++i)
    print_row(report.lanes[i].result, context.names[i], report.lanes[i].wrong, width);
  for (const ReferenceReport& ref : report.references) print_reference_row(ref, width);
  if (color != FieldKind::None) print_fields(report, color, context.names);
  if (color == FieldKind::Error)
    for (std::size_t k = 0; k < report.references.size(); ++k) print_reference_error(report, k);
  print_solver_work(report, context.names);
  for (std::size_t i = 0; i < report.lanes.size(); ++i) {
    const LaneResult& r = report.lanes[i].result;
    if (integrator_info(r.spec.kind).adaptive) {  // its own steps, and what its error control did
      std::printf("steps of %s: %.3g to %.3g s, %" PRId64 " accepted, %" PRId64 " refused by its error control\n",
                  context.names[i].c_str(), r.totals.smallest_step, r.totals.largest_step, r.totals.steps,
                  r.totals.rejected_steps);
      if (r.totals.projected_steps > 0)
        std::printf("%s: %" PRId64 " steps ended in a projected contact, a jump its error control does not see: "
                    "its tolerance bounds the error between contacts only (collision.model: barrier puts contact "
                    "in the ODE)\n", context.names[i].c_str(), r.totals.projected_steps);
      continue;
    }
    std::printf("step of %s: %s s, %s\n", context.names[i].c_str(), r.spec.step_text.c_str(),
                context.step_choice[i].c_str());
  }
}

std::vector<JsonObject> summary_lanes(const Model& model, const PipelineReport& report, FieldKind color,
                                      const SummaryContext& context) {
  std::vector<JsonObject> lanes;
  for (std::size_t i = 0; i < report.lanes.size(); ++i) {
    JsonObject lane = lane_summary(model, report.lanes[i].result, "lane");
    lane.text("step_choice", context.step_choice[i]).text("name", context.names[i]);
    const std::string& wrong = report.lanes[i].wrong;
    lane.text("result", lane_result(report.lanes[i].result, wrong)).text("wrong", wrong);
    lane.number("energy_rise", report.lanes[i].energy_rise);
    if (color != FieldKind::None) with_field(lane, report, i);
    if (color == FieldKind::Error) lane.boolean("unresolved", lane_unresolved(report, i, color));
    lanes.push_back(lane);
  }
  for (const ReferenceReport& ref : report.references) {
    JsonObject lane = lane_summary(model, ref.result, "reference");
    if (!ref.label.empty()) lane.text("name", "reference, " + ref.label);
    lanes.push_back(lane);
  }
  return lanes;
}

void print_breakdown(const TileGrid& grid, int legend_width, const PipelineReport& report, double wall) {
  double sim_cpu = 0.0;
  for (const LaneReport& r : report.lanes) sim_cpu += r.result.totals.cpu_seconds;
  for (const ReferenceReport& ref : report.references) sim_cpu += ref.result.totals.cpu_seconds;
  std::string outputs;
  for (const auto& [what, seconds] : report.output_seconds) {
    char buf[64];
    std::snprintf(buf, sizeof buf, ", %s %.1f s", what.c_str(), seconds);
    outputs += buf;
  }
  // The clip's own size where it differs: H.264 (yuv420p) takes even sizes, so an odd picture
  // is encoded a column or row larger (641x361 became 642x362 while this line said 641x361).
  const int width = grid.width() + legend_width, height = grid.height();
  const bool video = std::any_of(report.output_seconds.begin(), report.output_seconds.end(),
                                 [](const auto& o) { return o.first == "video"; });
  char encoded[64] = "";
  if (video && (even_size(width) != width || even_size(height) != height))
    std::snprintf(encoded, sizeof encoded, ", the video %dx%d (H.264 takes even sizes)", even_size(width),
                  even_size(height));
  std::fprintf(stderr,
               "compare: %ld time%s, %dx%d%s (%zu tiles of %dx%d), in %.1f s wall: simulate %.1f s cpu "
               "on %zu threads (the renderer waited %.1f s), render %.1f s%s\n",
               report.targets, report.targets == 1 ? "" : "s", width, height, encoded, report.lanes.size(),
               grid.cell_width(), grid.cell_height(), wall, sim_cpu, report.lanes.size() + report.references.size(),
               report.wait_seconds, report.render_seconds, outputs.c_str());
}

bool lane_unresolved(const PipelineReport& report, std::size_t i, FieldKind color) {
  const LaneResult* reference = lane_reference(report, i);
  return color == FieldKind::Error && reference && report.lanes[i].field_count > 0 && !report.lanes[i].result.divergence &&
         report.lanes[i].field_max < kUnresolvedFactor * reference->estimated_error;
}

JsonObject summary_reference(const ReferenceReport& report) {
  const LaneResult& ref = report.result;
  JsonObject json;
  if (!report.label.empty()) json.text("for", report.label);
  const bool adaptive = ref.adaptive_tolerance > 0.0;
  json.text("method", adaptive ? "dopri5 (adaptive)" : ref.spec.name())
      .number("dt", adaptive ? NAN : ref.spec.dt)
      .number("tolerance", adaptive ? ref.adaptive_tolerance : NAN)
      .number("check_dt", ref.check_dt > 0.0 ? ref.check_dt : NAN)
      .number("check_tolerance", adaptive ? ref.check_tolerance : NAN)
      .number("estimated_error_m", ref.estimated_error);
  if (!ref.cache.empty())  // computed or reused (lane_worker.h, LaneResult::cache)
    json.text("cache", ref.cache == "reused" ? "reused" : "computed")
        .text("cache_detail", ref.cache)
        .text("cache_file", ref.cache_file)
        .number("computed_cpu_seconds", ref.cache == "reused" ? ref.computed_cpu_seconds : ref.totals.cpu_seconds);
  return json;
}

}  // namespace clothsim::clip
