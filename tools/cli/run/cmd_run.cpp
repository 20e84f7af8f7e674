// clothsim run: one scene, one integrator: the frame pipeline (frame_pipeline.h) with one
// lane. Steps to each output frame (the scene's fps), records metrics, renders frames/video/a
// still if asked, writes the final state. A run that diverges ends there: its pictures show the
// last finite state with DIVERGED, the time and step this command prints.
// Exit 3 when the run diverges (metrics up to that point are kept; the state is not written);
// with --strict, exit 4 when an implicit step did not converge (every output is written).
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clip/frames/run_outputs.h"
#include "clip/compare/compare_summary.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/gl_options.h"
#include "clip/common/lanes.h"
#include "clip/common/memory_budget.h"
#include "clip/frames/run_budget.h"
#include "clip/common/scene_options.h"
#include "clip/common/summary_json.h"
#include "clip/frames/frame_pipeline.h"
#include "clip/frames/export_output.h"
#include "clip/frames/frame_sink.h"
#include "clip/frames/picture_options.h"
#include "clip/frames/pipeline_outputs.h"
#include "core/run/simulation.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "scene/build_model.h"
#include "scene/run_bounds.h"
#include "study/reference.h"

namespace clothsim::cli {
namespace {

struct RunOptions {
  SceneOptions scene;
  std::string frames_dir, video, metrics, state;
  std::optional<double> still_t;
  std::string still_out;
  int crf = VideoOptions{}.crf;
  std::string preset = VideoOptions{}.preset;
  bool strict = false;
  GlOptions gl;
  PictureOptions look;
  std::string summary;  // --summary FILE.json
  std::optional<std::string> iterations;  // --iterations N, as typed (given empty: refused)
  std::string export_path;  // --export PATH (export_output.h)
};

// Usage checks that need the scene: --still's time, --crf, --iterations.
void check_run_usage(const RunOptions& o, const SceneDef& scene) {
  if (o.still_t && o.still_out.empty()) throw UsageError("--still needs -o/--output FILE.png");
  if (!o.still_out.empty() && !o.still_t) throw UsageError("-o/--output goes with --still T");
  if (o.still_t && !(*o.still_t >= 0.0 && *o.still_t <= scene.duration))  // NaN too
    throw UsageError("--still: time " + number_text(*o.still_t) + " s is outside the run (0 to " +
                     number_text(scene.duration) + " s)");
  if (o.crf < 0 || o.crf > 51) throw UsageError("--crf: must be from 0 to 51");
  if (o.iterations) {  // checked on scratch settings: the scene's take them later
    MethodSettings probe;
    set_iterations(probe, scene.integrator, false, parse_iteration_option(*o.iterations, "--iterations"),
                   "--iterations");
  }
}

// --iterations N: the lane NAME:N of the scene's integrator written into the scene (scene/
// lane.h's apply_lane), as if its block said it, so the Model's defaults are the run's settings.
void apply_iterations(const RunOptions& o, SceneDef& scene) {
  if (!o.iterations) return;
  Lane lane;
  lane.kind = scene.integrator;
  lane.iterations = parse_iteration_option(*o.iterations, "--iterations");
  apply_lane(scene, lane);
}

// Every output is checked before any work, so a typo fails in milliseconds; returns --export's
// paths.
// With -n, an output that exists already is refused here too (exit 2), untouched.
std::vector<ExportPath> check_run_outputs(const RunOptions& o, int spheres) {
  std::vector<PathRole> outputs{{o.metrics, "--metrics"},      {o.state, "--state"},
                                {o.video, "--video"},          {o.still_out, "-o/--output"},
                                {o.summary, "--summary"},      {o.frames_dir, "--frames", true}};
  for (PathRole& r : export_roles(o.export_path, {}, spheres)) outputs.push_back(std::move(r));
  refuse_clashing_paths({{o.scene.path, "the scene"}}, outputs);
  if (!o.metrics.empty()) require_writable_parent(o.metrics, "--metrics");
  if (!o.state.empty()) require_writable_parent(o.state, "--state");
  if (!o.video.empty()) require_writable_parent(o.video, "--video");
  if (!o.still_out.empty()) require_png_name(o.still_out, "-o/--output");
  if (!o.still_out.empty()) require_writable_parent(o.still_out, "-o/--output");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  if (!o.frames_dir.empty()) refuse_existing_frames(o.frames_dir, "--frames");
  return checked_export_paths(o.export_path, {}, spheres);
}

// The summary line(s) on stdout: steps, cost and, for the implicit solve, its work.
void print_run_totals(const Model& model, IntegratorKind kind, double dt, const LaneResult& r,
                      const PipelineReport& report) {
  const RunTotals& t = r.totals;
  // CPU time of the stepping thread is the cost to compare between methods (wall time also
  // counts whatever else the machine is doing).
  std::printf("%s: %s, dt = %g s, %" PRId64 " steps to t = %.6g s, %" PRId64
              " force evaluations, %.3f s of wall time, %.3f s of CPU (%.3g s of CPU per simulated s)\n",
              model.name.c_str(), method_name(kind, model.implicit).c_str(), dt, t.steps, r.t, t.force_evals,
              t.sim_seconds, t.cpu_seconds, r.t > 0 ? t.cpu_seconds / r.t : 0.0);
  if (integrator_info(kind).iterations == IterationControl::Newton && model.implicit.solver == ImplicitSolver::Newton)
    std::printf("implicit solve: %" PRId64 " Newton iterations, %" PRId64
                " CG iterations (%" PRId64 " sparse factorizations), largest final residual %.3g, %" PRId64
                " steps not converged; %" PRId64 " contacts held in the solve, %" PRId64
                " post-step projections\n",
                t.newton_iterations, t.cg_iterations, t.factorizations, t.max_residual, t.unconverged_steps,
                t.contact_constraints, t.safety_projections);
  if (integrator_info(kind).adaptive) {
    std::printf("%s: %" PRId64 " accepted steps, %" PRId64 " refused by the error control (rtol %g, atol %g); "
                "steps from %.3g to %.3g s\n",
                std::string(integrator_name(kind)).c_str(), t.steps, t.rejected_steps, model.adaptive.rtol,
                model.adaptive.atol, t.smallest_step, t.largest_step);
    if (t.projected_steps > 0)
      std::printf("%s: %" PRId64 " steps ended in a projected contact, which the error control does not see "
                  "(a jump outside the ODE): the tolerance bounds the error between contacts only; use "
                  "collision.model: barrier for a contact it controls\n",
                  std::string(integrator_name(kind)).c_str(), t.projected_steps);
  }
  if (is_iterative_solver(kind))
    std::printf("%s: %" PRId64 " iterations, %" PRId64 " factorizations, %" PRId64
                " steps not converged (largest relative residual %.3g; measured with a tolerance only)\n",
                std::string(integrator_name(kind)).c_str(), t.newton_iterations, t.factorizations,
                t.unconverged_steps, t.max_residual);
  const LaneResult* reference = lane_reference(report, 0);
  if (reference && reference->adaptive_tolerance > 0.0)  // a smooth scene's (study/reference.h)
    std::printf("reference for --color error: dopri5 adaptive at tolerance %.0e (checked at %.0e), %" PRId64
                " force evaluations, %.3f s of CPU; its estimated error %.3g m\n",
                reference->adaptive_tolerance, reference->check_tolerance, reference->totals.force_evals,
                reference->totals.cpu_seconds, reference->estimated_error);
  else if (reference)
    std::printf("reference for --color error: %s at dt = %s s, %" PRId64 " force evaluations, %.3f s of CPU; its "
                "estimated error %.3g m (a run at twice its step)\n",
                reference->spec.name().c_str(), reference->spec.step_text.c_str(),
                reference->totals.force_evals, reference->totals.cpu_seconds,
                reference->estimated_error);
  if (reference && !reference->cache.empty())  // computed or reused (docs/compare.md)
    std::printf("reference for --color error: %s\n", reference_cache_text(*reference).c_str());
}

void write_run_summary(const RunOptions& o, const SceneDef& scene, const Model& model, const LaneResult& r,
                       const PipelineReport& report) {
  std::vector<JsonObject> lanes{lane_json(model.name, scene.integrator, scene.dt, r.totals,
                                          r.divergence ? std::optional<double>(r.divergence->t) : std::nullopt)
                                    .number("t_reached", r.t)
                                    .number("max_residual", r.totals.max_residual)};
  if (r.totals.wrong) lanes.front().number("wrong_at", r.totals.wrong->t).text("wrong", r.totals.wrong->reason);
  if (const LaneResult* reference = lane_reference(report, 0))
    lanes.push_back(lane_json(model.name, reference->spec.kind, reference->spec.dt, reference->totals, std::nullopt)
                        .text("role", "reference"));
  write_summary(o.summary, "run", scene.source, lanes);
}

// What the pipeline does for this run: render or not, which tables, the picture's look.
PipelineConfig run_config(const RunOptions& o, const SceneDef& scene, const Model& model,
                          const PictureLook& look, bool rendering) {
  PipelineConfig config;
  config.rendering = rendering;
  config.width = scene.render.width;
  config.height = scene.render.height;
  config.metrics = !o.metrics.empty();
  config.final_state = !o.state.empty();
  config.stop_when_all_frozen = true;  // run ends at divergence (exit 3)
  config.command = "run";
  apply_look(look, config);
  config.scene_render = scene.render;
  if (look.camera_auto)
    config.camera = auto_camera(model, scene.render, static_cast<double>(scene.render.width) / scene.render.height);
  return config;
}

// WRONG: finite, but not this scene's physics (the run's own verdict, else compare's rule on a
// reference it was coloured against), said on stderr. Returns whether the run reads WRONG.
bool say_wrong(const std::string& source, const RunTotals& t, const PipelineReport& report) {
  const std::string& wrong = report.lanes.front().wrong;
  if (t.wrong)
    std::fprintf(stderr, "clothsim: %s: WRONG at step %" PRId64 ", t = %.6g s: %s\n", source.c_str(), t.wrong->step,
                 t.wrong->t, t.wrong->reason.c_str());
  else if (!wrong.empty())
    std::fprintf(stderr, "clothsim: %s: %s\n", source.c_str(), wrong.c_str());
  return t.wrong || !wrong.empty();
}

int run_command(const RunOptions& o) {
  install_interrupt_handler();  // first: a signal during setup is then seen, not fatal, and temporaries go
  SceneDef scene = load_scene_with_options(o.scene);
  check_run_usage(o, scene);
  apply_iterations(o, scene);
  const Lane lane{scene.integrator, scene.dt, step_string(scene.dt), false};
  const bool rendering = !o.frames_dir.empty() || !o.video.empty() || o.still_t;
  PictureLook look = resolve_picture_look(o.look, scene, {lane}, /*compare=*/false);
  if (!rendering && o.export_path.empty()) look = PictureLook{};  // no colour, no reference lane
  if (look.reference) {
    const std::string too_long = run_bounds_problem(scene.duration, look.reference->dt, scene.render.fps);
    if (!too_long.empty())
      throw UsageError("--reference (" + look.reference->spelling() +
                       ", for --color error): " + too_long);
  }
  const double fps = scene.render.fps;
  // A still alone needs the run only up to its time; any other output needs the whole run,
  // and the final state is the one at the end even when that is not a whole frame.
  const bool still_only = o.still_t && o.metrics.empty() && o.state.empty() && o.frames_dir.empty() &&
                          o.video.empty() && o.summary.empty() && o.export_path.empty();
  // Frame by frame even with no picture or metrics to take: progress counts frames.
  // A colour scale from the data needs the first second even when the still comes sooner.
  const bool scale_from_data = look.color != FieldKind::None && !look.color_range;
  const double end = !still_only ? scene.duration
                     : scale_from_data ? std::max(*o.still_t, std::min(kColorScaleWindow, scene.duration))
                                       : *o.still_t;
  TargetPlan targets(end, fps, !still_only, {}, o.still_t.value_or(-1.0), /*to_end=*/!still_only);
  if (scale_from_data) targets.with_scale_window(kColorScaleWindow);

  // Peak memory, estimated and checked before the Model, the renderer or the encoder exist.
  const int w = scene.render.width, h = scene.render.height;
  RunPictures pictures{rendering, w, h, !o.video.empty(), !o.state.empty(), {}, &targets};
  for (const ExportPath& e : export_paths(o.export_path, {})) pictures.export_format = e.format;  // (parsed only)
  run_budget(scene, look, pictures).check(scene.source, o.scene.max_memory);
  // Then the outputs, whose checks make the export's folder: a run refused above leaves none.
  const std::vector<ExportPath> exports = check_run_outputs(o, static_cast<int>(scene.spheres.size()));

  const Model model = build_model(scene);
  fit_reference_to_model(look, model, scene, {lane});
  const IntegratorKind kind = scene.integrator;
  const double dt = scene.dt;

  std::unique_ptr<Renderer> renderer;
  if (rendering) renderer = make_renderer(o.gl);
  const PipelineConfig config = run_config(o, scene, model, look, rendering);
  FramePipeline pipeline(model, targets, {lane}, config, renderer.get());
  const PngText png_text = renderer ? with_renderer(frame_metadata(model, kind, dt), *renderer) : PngText{};
  if (!o.metrics.empty())
    pipeline.add(make_metrics_output(std::make_unique<MetricsWriter>(o.metrics, model, kind, dt), o.metrics, 0));
  if (!o.frames_dir.empty()) pipeline.add(make_frames_output(make_png_sequence_sink(o.frames_dir, png_text), 0));
  if (!o.video.empty())
    pipeline.add(make_video_output(make_video_sink(o.video, VideoOptions{fps, o.crf, o.preset}), o.video, Composer{}));
  if (o.still_t) pipeline.add(make_still_output(o.still_out, Composer{}, png_text));
  add_export_outputs(pipeline, exports, model, {}, fps, look.color == FieldKind::Error);
  std::vector<std::string> after;  // written once the pipeline is through
  for (const std::string* out : {&o.state, &o.summary})
    if (!out->empty()) after.push_back(*out);
  const PipelineReport report = pipeline.run("run " + model.name, after);
  const LaneResult& r = report.lanes.front().result;

  const RunTotals& t = r.totals;
  print_run_totals(model, kind, dt, r, report);
  RunFiles files({o.metrics, o.video, o.still_t ? o.still_out : "", o.frames_dir, o.export_path}, after);  // run_outputs.h
  files.write(o.summary, [&] { write_run_summary(o, scene, model, r, report); });  // a diverged run too
  if (r.divergence) {
    const Divergence& d = *r.divergence;
    std::fprintf(stderr, "clothsim: %s: diverged at step %" PRId64 ", t = %.6g s: %s\n",
                 scene.source.c_str(), d.step, d.t, d.reason.c_str());
    return kDiverged;
  }
  files.write(o.state, [&] { write_state_csv(o.state, model, *r.final_state); });
  const bool wrong = say_wrong(scene.source, t, report);
  if (o.strict && t.unconverged_steps > 0) {
    std::fprintf(stderr,
                 "clothsim: %s: --strict: %" PRId64 " of %" PRId64
                 " steps did not converge (largest final residual %.3g)\n",
                 scene.source.c_str(), t.unconverged_steps, t.steps, t.max_residual);
    return kNotConverged;
  }
  if (o.strict && wrong) return kWrong;
  return kOk;
}

}  // namespace

void add_run_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* sub = app.add_subcommand(
      "run", "Run one scene with one integrator: metrics, final state, frames, video, a still");
  add_scene_options(sub, o->scene, /*single_run=*/true);
  add_gl_options(sub, o->gl);
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  add_picture_look_options(sub, o->look, /*compare=*/false);
  sub->add_option("--summary", o->summary, "Write what the run did as JSON (docs/summary.md)")->type_name("FILE.json");
  sub->footer(std::string(
      "Prints a summary (steps, force evaluations, wall time; for implicit_euler its Newton and CG\n"
      "work, steps not converged, contacts held in the solve and post-step projections) on stdout.\n"
      "Exits 3 when the run diverges (non-finite state, strain or kinetic energy past the scene's\n"
      "divergence bounds), saying at which step and time and why; --metrics is then kept up to\n"
      "that point and --state is not written. With --strict, exits 4 when any implicit step did\n"
      "not converge, saying how many (all outputs are still written). A run that reads WRONG (energy\n"
      "made with no work done, or strain past its bound: docs/integrators.md) says so on stderr, and\n"
      "with --strict exits 5. Outputs are created with\n"
      "no name (O_TMPFILE) and named only when complete: nothing is left behind, even by SIGKILL.\n") + kExitCodesHelp);
  sub->add_option("--iterations", o->iterations,
                  "Iterations per step: xpbd, projective_dynamics and vbd's sweeps, implicit_euler's "
                  "Newton cap (1: Baraff & Witkin's single linearised step)")
      ->type_name("N");
  sub->add_flag("--strict", o->strict,
                "Exit 4 if any step ended above its tolerance (implicit_euler's Newton, a solver's tol=), "
                "5 if the run reads WRONG");
  sub->add_option("--frames", o->frames_dir, "Write frame_00000.png... into DIR at --fps")
      ->type_name("DIR");
  sub->add_option("--video", o->video, "Write an H.264 MP4 of the run")->type_name("FILE.mp4");
  sub->add_option("--metrics", o->metrics,
                  "Write one CSV row per output frame: step,t,kinetic,spring_potential,"
                  "gravity_potential,total_energy,max_strain,contacts,force_evals,...")
      ->type_name("FILE.csv");
  sub->add_option("--state", o->state, "Write the final state: id,x,y,z,vx,vy,vz per particle")
      ->type_name("FILE.csv");
  add_export_option(sub, o->export_path);
  sub->add_option("--still", o->still_t, "Render one frame at time T (s) to -o/--output")->type_name("T");
  sub->add_option("-o,--output,--out", o->still_out, "PNG file for --still")->type_name("FILE.png");
  add_picture_options(sub, o->scene, "the frames", "--frames, --video and --metrics rows");
  sub->add_option("--crf", o->crf, "Video quality, x264 CRF 0 (lossless) .. 51")->capture_default_str();
  sub->add_option("--preset", o->preset, "x264 preset (ultrafast .. veryslow)")->capture_default_str();
  sub->callback([o, &command] { command = [o] { return run_command(*o); }; });
}

}  // namespace clothsim::cli
