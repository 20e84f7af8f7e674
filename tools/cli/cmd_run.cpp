// clothsim run: one scene, one integrator. Steps to each output frame (the scene's fps),
// records metrics, renders frames/video/a still if asked, writes the final state.
// Exit 3 when the run diverges (metrics up to that point are kept; the state is not written);
// with --strict, exit 4 when an implicit step did not converge (every output is written).
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "commands.h"
#include "frame_sink.h"
#include "gl_options.h"
#include "summary_json.h"
#include "memory_budget.h"
#include "memory_estimate.h"
#include "png_io.h"
#include "renderer.h"
#include "run_outputs.h"
#include "scene_options.h"
#include "simulation.h"
#include "snapshot.h"

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
  std::string summary;  // --summary FILE.json
};

RenderFrame snapshot_of(const Run& run) {
  const SnapshotText text{overlay_lines(run.model(), run.kind(), run.dt(), run.state().t), {}};
  return make_render_frame(run.model(), run.state(), text);
}

int run_command(const RunOptions& o) {
  install_interrupt_handler();  // first: a signal during setup is then seen, not fatal, and temporaries go
  const SceneDef scene = load_scene_with_options(o.scene);
  if (o.still_t && o.still_out.empty()) throw UsageError("--still needs -o/--output FILE.png");
  if (!o.still_out.empty() && !o.still_t) throw UsageError("-o/--output goes with --still T");
  if (o.still_t && (*o.still_t < 0.0 || *o.still_t > scene.duration))
    throw UsageError("--still: time " + std::to_string(*o.still_t) + " s is outside the run (0 to " +
                     std::to_string(scene.duration) + " s)");
  if (o.crf < 0 || o.crf > 51) throw UsageError("--crf: must be from 0 to 51");

  // Every output is checked before any work, so a typo fails in milliseconds.
  // With -n, an output that exists already is refused here too (exit 2), untouched.
  if (!o.metrics.empty()) require_writable_parent(o.metrics, "--metrics");
  if (!o.state.empty()) require_writable_parent(o.state, "--state");
  if (!o.video.empty()) require_writable_parent(o.video, "--video");
  if (!o.still_out.empty()) require_writable_parent(o.still_out, "-o/--output");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  if (!o.frames_dir.empty()) refuse_existing_frames(o.frames_dir, "--frames");

  // Peak memory, estimated and checked before the Model, the renderer or the encoder exist.
  const bool rendering = !o.frames_dir.empty() || !o.video.empty() || o.still_t;
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  budget.add(std::string(integrator_name(scene.integrator)), run_bytes(scene, scene.integrator));
  if (rendering) {
    const int w = scene.render.width, h = scene.render.height;
    // The render target, the frame and up to 3 frames queued for the PNG writer.
    budget.add("renderer " + std::to_string(w) + "x" + std::to_string(h),
               kRendererBytes + render_bytes(w, h, scene.render.samples) + 4.0 * w * h * 4);
  }
  if (!o.video.empty()) budget.add("encoder", encoder_bytes(scene.render.width, scene.render.height));
  budget.check(scene.source, o.scene.max_memory);

  const Model model = build_model(scene);
  const IntegratorKind kind = scene.integrator;
  const double dt = scene.dt;
  const double fps = scene.render.fps;
  // A still alone needs the run only up to its time; any other output needs the whole run.
  const bool still_only = o.still_t && o.metrics.empty() && o.state.empty() && o.frames_dir.empty() &&
                          o.video.empty() && o.summary.empty();
  const double end = still_only ? *o.still_t : scene.duration;
  const long frames = static_cast<long>(std::floor(end * fps + 1e-9)) + 1;  // t = 0 included

  std::unique_ptr<Renderer> renderer;
  if (rendering) renderer = make_renderer(o.gl);
  std::unique_ptr<MetricsWriter> metrics;
  if (!o.metrics.empty()) metrics = std::make_unique<MetricsWriter>(o.metrics, model, kind, dt);
  std::unique_ptr<FrameSink> png_sink, video_sink;
  const PngText png_text = renderer ? with_renderer(frame_metadata(model, kind, dt), *renderer) : PngText{};
  if (!o.frames_dir.empty()) png_sink = make_png_sequence_sink(o.frames_dir, png_text);
  if (!o.video.empty()) video_sink = make_video_sink(o.video, VideoOptions{fps, o.crf, o.preset});

  Run run(model, kind, dt);
  run.set_stop_check([] { return interrupted(); });  // polled before every step
  bool still_written = false;
  // A signal: every output not complete is dropped (the sinks remove their temporaries), and
  // the message says what stays on disk (PNGs already written under --frames, a still taken).
  const auto stop_here = [&]() -> RuntimeFailure {
    std::vector<std::string> kept, lost;
    if (png_sink) {
      const std::string left = png_sink->abandon();
      if (!left.empty()) kept.push_back(left);
    }
    if (video_sink) video_sink->abandon();
    if (o.still_t && still_written) kept.push_back(o.still_out);
    for (const std::string* out : {&o.metrics, &o.video, &o.state, &o.summary})
      if (!out->empty()) lost.push_back(*out);
    if (o.still_t && !still_written) lost.push_back(o.still_out);
    return RuntimeFailure(interruption_message(run.state().t, kept, lost));
  };
  Progress progress("run " + model.name, frames, "frames");
  RenderFrame last_good;  // frame 0 (t = 0) is always good: no step has been taken
  bool still_done = !o.still_t;
  const auto take_still = [&] {
    run.advance_to(*o.still_t);
    if (run.stopped()) throw stop_here();
    if (!run.diverged()) {
      write_png(o.still_out, renderer->render(snapshot_of(run)), png_text);
      still_written = true;
    }
    still_done = true;
  };
  for (long k = 0; k < frames; ++k) {
    if (interrupted()) throw stop_here();
    const double target = std::min(static_cast<double>(k) / fps, end);
    if (!still_done && *o.still_t <= target) take_still();
    const bool ok = run.advance_to(target);
    if (run.stopped()) throw stop_here();
    if (metrics) metrics->row(run.metrics());
    if (png_sink || video_sink) {
      // A run that diverged freezes on its last good frame, as a tile of `compare` does.
      RenderFrame frame = ok ? snapshot_of(run) : last_good;
      if (ok) last_good = frame;
      else mark_diverged(frame, *run.divergence());
      const Image image = renderer->render(frame);
      if (png_sink) png_sink->add(static_cast<int>(k), run.state().t, image);
      if (video_sink) video_sink->add(static_cast<int>(k), run.state().t, image);
    }
    progress.update(k + 1);
    if (!ok) break;
  }
  if (!still_done && !run.diverged()) take_still();  // a still after the last whole frame
  if (!run.diverged()) run.advance_to(end);  // an end that is not a whole frame
  if (run.stopped() || interrupted()) throw stop_here();
  progress.finish();

  if (metrics) metrics->commit();
  if (png_sink) png_sink->finish();
  if (video_sink) video_sink->finish();

  // CPU time of the stepping thread is the cost to compare between methods (wall time also
  // counts whatever else the machine is doing).
  const RunTotals& t = run.totals();
  const double simulated = run.state().t;
  std::printf("%s: %s, dt = %g s, %" PRId64 " steps to t = %.6g s, %" PRId64
              " force evaluations, %.3f s of wall time, %.3f s of CPU (%.3g s of CPU per simulated s)\n",
              model.name.c_str(), std::string(integrator_name(kind)).c_str(), dt, t.steps,
              simulated, t.force_evals, t.sim_seconds, t.cpu_seconds,
              simulated > 0 ? t.cpu_seconds / simulated : 0.0);
  if (kind == IntegratorKind::ImplicitEuler)
    std::printf("implicit solve: %" PRId64 " Newton iterations, %" PRId64
                " CG iterations (%" PRId64 " sparse factorizations), largest final residual %.3g, %" PRId64
                " steps not converged; %" PRId64 " contacts held in the solve, %" PRId64
                " post-step projections\n",
                t.newton_iterations, t.cg_iterations, t.factorizations, t.max_residual, t.unconverged_steps,
                t.contact_constraints, t.safety_projections);
  if (!o.summary.empty())  // written for a diverged run too: that is a result
    write_summary(o.summary, "run", scene.source,
                  {lane_json(model.name, kind, dt, t,
                             run.diverged() ? std::optional<double>(run.divergence()->t) : std::nullopt)
                       .number("t_reached", run.state().t)
                       .number("max_residual", t.max_residual)});
  if (run.diverged()) {
    const Divergence& d = *run.divergence();
    std::fprintf(stderr, "clothsim: %s: diverged at step %" PRId64 ", t = %.6g s: %s\n",
                 scene.source.c_str(), d.step, d.t, d.reason.c_str());
    return kDiverged;
  }
  if (!o.state.empty()) write_state_csv(o.state, model, run.state());
  if (o.strict && t.unconverged_steps > 0) {
    std::fprintf(stderr,
                 "clothsim: %s: --strict: %" PRId64 " of %" PRId64
                 " implicit steps did not converge (largest final residual %.3g)\n",
                 scene.source.c_str(), t.unconverged_steps, t.steps, t.max_residual);
    return kNotConverged;
  }
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
  sub->add_option("--summary", o->summary, "Write what the run did as JSON (docs/summary.md)")->type_name("FILE.json");
  sub->footer(std::string(
      "Prints a summary (steps, force evaluations, wall time; for implicit_euler its Newton and CG\n"
      "work, steps not converged, contacts held in the solve and post-step projections) on stdout.\n"
      "Exits 3 when the run diverges (non-finite state, strain or kinetic energy past the scene's\n"
      "divergence bounds), saying at which step and time and why; --metrics is then kept up to\n"
      "that point and --state is not written. With --strict, exits 4 when any implicit step did\n"
      "not converge, saying how many (all outputs are still written). Outputs are created with\n"
      "no name (O_TMPFILE) and named only when complete: nothing is left behind, even by SIGKILL.\n") + kExitCodesHelp);
  sub->add_flag("--strict", o->strict,
                "Exit 4 if any implicit_euler step ended above its Newton tolerance");
  sub->add_option("--frames", o->frames_dir, "Write frame_00000.png... into DIR at --fps")
      ->type_name("DIR");
  sub->add_option("--video", o->video, "Write an H.264 MP4 of the run")->type_name("FILE.mp4");
  sub->add_option("--metrics", o->metrics,
                  "Write one CSV row per output frame: step,t,kinetic,spring_potential,"
                  "gravity_potential,total_energy,max_strain,contacts,force_evals,...")
      ->type_name("FILE.csv");
  sub->add_option("--state", o->state, "Write the final state: id,x,y,z,vx,vy,vz per particle")
      ->type_name("FILE.csv");
  sub->add_option("--still", o->still_t, "Render one frame at time T (s) to -o/--output")->type_name("T");
  sub->add_option("-o,--output,--out", o->still_out, "PNG file for --still")->type_name("FILE.png");
  add_picture_options(sub, o->scene, "the frames", "--frames, --video and --metrics rows");
  sub->add_option("--crf", o->crf, "Video quality, x264 CRF 0 (lossless) .. 51")->capture_default_str();
  sub->add_option("--preset", o->preset, "x264 preset (ultrafast .. veryslow)")->capture_default_str();
  sub->callback([o, &command] { command = [o] { return run_command(*o); }; });
}

}  // namespace clothsim::cli
