// clothsim compare SCENE [--integrators NAME[@STEP],... | course] [--layout auto] [--video FILE.mp4]
//                        [--frames DIR] [--dt S | --dt name=S,...] [--duration S] [--set K=V]...
//                        [--sheet FILE.png --times 0.5,1,2,4] [--still T -o FILE.png]
//                        [--color error|strain|speed|checker] [--reference NAME@STEP] [--inset energy]
//                        [--width W --height H] [--crf Q] [--preset P]
//
// The scene is loaded once and built into one Model; one lane per integrator and step runs on
// its own thread through the frame pipeline (frame_pipeline.h), which colours, labels and
// renders each lane's picture into a tile and feeds the outputs: the tiled clip, each lane's
// PNGs, the contact sheet, the still. A lane that diverges shows its last finite state with
// a DIVERGED banner while the others go on: in compare, divergence is a result (exit 0),
// shown in the clip and in the summary table.
//
// By default the tiles are coloured by each particle's distance from a reference lane (RK4 at
// a quarter of the smallest step, or at its predicted stable step where that is smaller:
// fit_reference_to_model) run alongside and never shown, on one logarithmic scale with
// a colour bar, and each tile counts its force evaluations: which method is more accurate and
// which is cheaper, on screen.
//
// Outputs are checked before any simulation (unknown integrator or layout, unwritable
// paths, bad --dt or --times: milliseconds, exit 2 or 1), created without a name and
// named when complete. SIGINT / SIGTERM stop every lane before its next step, drop the
// incomplete outputs and exit 130 / 143 saying what stays: PNGs already written under
// --frames (each is complete).
//
// Frame k is the state at t = k / fps for k = 0 .. floor(duration * fps), as in `run`.
// The summary (stdout) has one row per lane (and the reference's); the time breakdown
// (stderr) says where the wall time went.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compare_plan.h"
#include "cli/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/gl_options.h"
#include "cli/common/lanes.h"
#include "cli/common/memory_budget.h"
#include "cli/common/progress.h"
#include "cli/common/scene_options.h"
#include "cli/common/summary_json.h"
#include "cli/frames/frame_pipeline.h"
#include "cli/frames/frame_sink.h"
#include "cli/frames/picture_options.h"
#include "cli/frames/pipeline_outputs.h"
#include "cli/run/run_outputs.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "video/tiling.h"
#include "video/video_writer.h"

namespace clothsim::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct CompareOptions {
  SceneOptions scene;
  std::string integrators = default_comparison_list();  // the course's four, by name
  std::string layout = "auto";
  std::string video, frames_dir, dt, sheet, times, still_out;
  std::optional<double> still_t;
  int crf = VideoOptions{}.crf;
  std::string preset = VideoOptions{}.preset;
  GlOptions gl;
  PictureOptions look;
  std::string summary;  // --summary FILE.json
};

// The result column: what became of a lane.
std::string lane_result(const LaneResult& r) {
  char result[192];
  if (r.divergence)
    std::snprintf(result, sizeof result, "DIVERGED at t = %.6g s (step %" PRId64 "): %s", r.divergence->t,
                  r.divergence->step, r.divergence->reason.c_str());
  else if (r.totals.unconverged_steps > 0)
    std::snprintf(result, sizeof result,
                  "NOT CONVERGED: %" PRId64 " of %" PRId64 " steps, max residual %.2g (to t = %.4g s)",
                  r.totals.unconverged_steps, r.totals.steps, r.totals.max_residual, r.t);
  else
    std::snprintf(result, sizeof result, "ok to t = %.4g s", r.t);
  return result;
}

void print_row(const LaneResult& r, const std::string& name) {
  // Cost per simulated second over the time actually simulated (up to divergence).
  const double simulated = r.divergence ? r.divergence->t : r.t;
  std::printf("%-30s %10.3g %10" PRId64 " %13" PRId64 " %9.3f %14.1f  %s\n", name.c_str(), r.spec.dt, r.totals.steps,
              r.totals.force_evals, r.totals.cpu_seconds, simulated > 0 ? 1e3 * r.totals.cpu_seconds / simulated : 0.0,
              lane_result(r).c_str());
}

void print_summary(const Model& model, const PipelineReport& report, FieldKind color) {
  std::printf("%s: %zu lanes\n", model.name.c_str(), report.lanes.size());
  std::printf("%-30s %10s %10s %13s %9s %14s  %s\n", "lane", "dt_s", "steps", "force_evals", "cpu_s",
              "cpu_ms_per_s", "result");
  for (const LaneResult& r : report.lanes) print_row(r, r.spec.name());
  if (report.reference) print_row(*report.reference, report.reference->spec.name() + " (reference)");
  // What the implicit solve did, beside the table (0 for the explicit family, so not a column):
  // contacts it held as constraints, and particles the post-step projection still had to move.
  // The colouring in numbers: how far each lane strayed from the reference (or how strained,
  // how fast), the largest over the clip and at its end.
  if (color != FieldKind::None)
    for (std::size_t i = 0; i < report.lanes.size(); ++i) {
      const LaneResult& r = report.lanes[i];
      // Which frames the numbers cover: a clip's every frame, a sheet's or a still's only the
      // times it shows (and the colour scale's first second). A lane that diverged was
      // measured only up to its last frame before the blow-up: say so, or "largest 0 m" would
      // read as a perfect lane. So was every lane, when the reference it is measured against
      // diverged.
      const bool reference_diverged = color == FieldKind::Error && report.reference && report.reference->divergence;
      std::string values, measured = " (never measured";  // never: no number to quote, the note says why
      if (report.field_count[i] > 0) {
        char text[160];
        std::snprintf(text, sizeof text, " largest %.3g%s, at the end %.3g%s", report.field_max[i],
                      field_unit(color).c_str(), report.field_last[i], field_unit(color).c_str());
        values = text;
        // A lane whose step is longer than the frame interval stands on one state for several
        // frames: how many states those frames showed, where it is fewer.
        const long frames = report.field_count[i], states = report.field_states[i];
        char distinct[64] = "";
        if (states < frames)
          std::snprintf(distinct, sizeof distinct, " (%ld distinct state%s of the lane)", states, states == 1 ? "" : "s");
        if (frames == 1)
          std::snprintf(text, sizeof text, " (measured at 1 frame, t = %.4g s", report.field_last_t[i]);
        else
          std::snprintf(text, sizeof text, " (measured at %ld frames%s, t = %.4g to %.4g s", frames, distinct,
                        report.field_first_t[i], report.field_last_t[i]);
        measured = text;
      }
      char why[80] = "";
      if (r.divergence)
        std::snprintf(why, sizeof why, "; it diverged at t = %.6g s", r.divergence->t);
      else if (reference_diverged)
        std::snprintf(why, sizeof why, "; the reference diverged at t = %.6g s", report.reference->divergence->t);
      measured += std::string(why) + ")";
      std::printf("%s @ %s s: %s%s%s%s\n", r.spec.name().c_str(), r.spec.step_text.c_str(),
                  std::string(field_kind_name(color)).c_str(),
                  color == FieldKind::Error && report.reference
                      ? (" against " + report.reference->spec.name() + " @ " + report.reference->spec.step_text + " s:").c_str()
                      : ":",
                  values.c_str(), measured.c_str());
    }
  for (const LaneResult& r : report.lanes)
    if (r.spec.fixed_point)  // the course's one-iteration fixed point: no Newton, no CG, no contacts held
      std::printf("%s @ %s s: %" PRId64 " fixed-point iterations; post-step projections %" PRId64 "\n",
                  r.spec.name().c_str(), r.spec.step_text.c_str(), r.totals.newton_iterations,
                  r.totals.safety_projections);
    else if (r.spec.kind == IntegratorKind::ImplicitEuler)
      std::printf("%s @ %s s: %" PRId64 " Newton and %" PRId64 " CG iterations (%" PRId64
                  " sparse factorizations), largest final residual %.2g; "
                  "contacts held in the solve %" PRId64 ", post-step projections %" PRId64 "\n",
                  r.spec.name().c_str(), r.spec.step_text.c_str(), r.totals.newton_iterations, r.totals.cg_iterations,
                  r.totals.factorizations, r.totals.max_residual, r.totals.contact_constraints,
                  r.totals.safety_projections);
}

JsonObject lane_summary(const Model& model, const LaneResult& r, const std::string& role) {
  return lane_json(model.name, r.spec.kind, r.spec.dt, r.totals,
                   r.divergence ? std::optional<double>(r.divergence->t) : std::nullopt)
      .number("t_reached", r.t)
      .text("lane", r.spec.spelling())
      .text("role", role);
}

// A lane's colouring field in numbers (NaN, written null, when it was never coloured).
JsonObject& with_field(JsonObject& lane, const PipelineReport& report, std::size_t i) {
  return lane.number("field_max", report.field_max[i])
      .number("field_last", report.field_last[i])
      .number("field_frames", static_cast<double>(report.field_count[i]))
      .number("field_states", static_cast<double>(report.field_states[i]))
      .number("field_first_t", report.field_first_t[i])
      .number("field_last_t", report.field_last_t[i]);
}

int compare_command(const CompareOptions& o) {
  const auto wall_start = Clock::now();
  install_interrupt_handler();  // first: Ctrl-C during setup is then seen at the first frame

  // 1. Everything that can be wrong, before any simulation.
  if (o.sheet.empty() != o.times.empty())
    throw UsageError(o.sheet.empty() ? "--times goes with --sheet FILE.png"
                                     : "--sheet needs --times T1,T2,... (the columns)");
  if (o.still_t.has_value() != !o.still_out.empty())
    throw UsageError(o.still_t ? "--still needs -o/--output FILE.png" : "-o/--output goes with --still T");
  // A comparison that writes nothing would simulate every lane for nothing (the table it
  // prints is also in --summary): refused before any work.
  if (o.video.empty() && o.frames_dir.empty() && o.sheet.empty() && !o.still_t && o.summary.empty())
    throw UsageError("nothing to write: give --video FILE.mp4, --frames DIR, --sheet FILE.png, "
                     "--still T -o FILE.png or --summary FILE.json");
  try {
    validate_video_options(VideoWriterOptions{30.0, o.crf, o.preset});
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--video: ") + e.what());
  }
  const SceneDef scene = load_scene_with_options(o.scene);
  const std::vector<LaneSpec> lanes = parse_lanes(o.integrators, o.dt, scene.dt);
  GridLayout layout;
  try {
    layout = parse_layout(o.layout, static_cast<int>(lanes.size()));
  } catch (const LayoutError& e) {
    throw UsageError(std::string("--layout: ") + e.what());
  }
  const bool with_frames = !o.video.empty() || !o.frames_dir.empty();
  const bool rendering = with_frames || !o.sheet.empty() || o.still_t;
  PictureLook look = resolve_picture_look(o.look, scene, lanes, /*compare=*/true);
  if (!rendering) {
    // A summary alone: no pictures. The field is measured only when --color asks for it (the
    // default reference, RK4 at a quarter step, costs several times the lanes); its scale is
    // then not chosen (nothing is drawn with it).
    if (o.look.color && look.color != FieldKind::None) {
      if (!look.color_range) look.color_range = ColorRange{1e-6, 1e-3};
    } else {
      if (look.color != FieldKind::None && !o.summary.empty() && !quiet())
        std::fprintf(stderr, "compare: no pictures, so no %s measured; --color %s puts it in the summary\n",
                     std::string(field_kind_name(look.color)).c_str(), std::string(field_kind_name(look.color)).c_str());
      look = PictureLook{};
    }
  }
  refuse_shared_outputs({{o.video, "--video"}, {o.sheet, "--sheet"}, {o.still_out, "-o/--output"},
                         {o.summary, "--summary"}, {o.frames_dir, "--frames"}});
  if (!o.video.empty()) require_writable_parent(o.video, "--video");
  if (!o.sheet.empty()) require_writable_parent(o.sheet, "--sheet");
  if (!o.still_out.empty()) require_writable_parent(o.still_out, "-o/--output");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  if (!o.frames_dir.empty() && fs::exists(o.frames_dir) && !fs::is_directory(o.frames_dir))
    throw RuntimeFailure("cannot write --frames into " + o.frames_dir + ": not a directory");
  const std::vector<std::string> lane_dirs = lane_directories(lanes);
  if (!o.frames_dir.empty())
    for (const std::string& d : lane_dirs) refuse_existing_frames((fs::path(o.frames_dir) / d).string(), "--frames");
  for (const LaneSpec& l : lanes) {  // every lane's steps, and the reference's, bounded like the scene's
    const std::string too_long = run_bounds_problem(scene.duration, l.dt, scene.render.fps);
    if (!too_long.empty()) throw UsageError("--dt (" + l.spelling() + "): " + too_long);
  }
  if (look.reference) {
    const std::string too_long = run_bounds_problem(scene.duration, look.reference->dt, scene.render.fps);
    if (!too_long.empty())
      throw UsageError("--reference (" + look.reference->spelling() +
                       ", for --color error): " + too_long + "; give --reference NAME@STEP or --color checker");
  }
  const std::vector<double> sheet_times =
      o.sheet.empty() ? std::vector<double>{} : parse_times(o.times, scene.duration);
  if (o.still_t && !(*o.still_t >= 0.0 && *o.still_t <= scene.duration + 1e-9))
    throw UsageError("--still: " + number_text(*o.still_t) + " s is outside the run (0 to " +
                     number_text(scene.duration) + " s)");
  const int width = scene.render.width, height = scene.render.height;  // the whole grid's (--width/--height)
  std::optional<TileGrid> grid;
  try {
    grid.emplace(TileGrid::fit(layout, width, height));
  } catch (const LayoutError& e) {
    throw UsageError(std::string("--width/--height: ") + e.what());
  }
  const double fps = scene.render.fps;
  TargetPlan targets(scene.duration, fps, with_frames, sheet_times, o.still_t.value_or(-1.0));
  if (look.color != FieldKind::None && !look.color_range) targets.with_scale_window(kColorScaleWindow);

  // Peak memory, estimated and checked before the Model, the renderer or the encoder exist:
  // one Model (and a copy per fixed-point lane), a run per lane and the reference, the
  // renderer at tile size, the tiles, the grid, the PNG writers' queues (3 tiles each), the
  // contact sheet's cells, the first second held for the colour scale, and the encoder.
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  for (const LaneSpec& l : lanes)
    budget.add(l.spelling(),
               run_bytes(scene, l.kind) + kLaneThreadBytes + (l.fixed_point ? model_bytes(scene) : 0.0));
  if (look.reference) {
    budget.add("reference " + look.reference->name(), run_bytes(scene, look.reference->kind) + kLaneThreadBytes);
    std::vector<double> steps;
    for (const LaneSpec& l : lanes) steps.push_back(l.dt);
    budget.add("reference positions at the lanes' times", reference_positions_bytes(scene, steps, targets, kLaneQueueCapacity));
  }
  if (rendering) {
    const double n = static_cast<double>(lanes.size());
    const double tile = 4.0 * grid->cell_width() * grid->cell_height(), canvas = 4.0 * grid->width() * grid->height();
    budget.add("renderer and images " + std::to_string(grid->width()) + "x" + std::to_string(grid->height()),
               kRendererBytes + render_bytes(grid->cell_width(), grid->cell_height(), scene.render.samples) +
                   n * tile + 2.0 * canvas + (o.frames_dir.empty() ? 0.0 : 3.0 * n * tile));
    if (!o.sheet.empty())
      budget.add("contact sheet", 2.0 * n * static_cast<double>(sheet_times.size()) * tile);
    if (look.color != FieldKind::None && !look.color_range)
      budget.add("the first second, held for the colour scale",
                 held_frames_bytes(scene, lanes.size(), std::min(1.0, scene.duration) * fps + 1.0));
  }
  if (!o.video.empty()) budget.add("encoder", encoder_bytes(grid->width(), grid->height()));
  budget.check(scene.source, o.scene.max_memory);
  const Model model = build_model(scene);
  fit_reference_to_model(look, model, scene, lanes);

  // 2. The pipeline and its outputs (each removes its temporary if destroyed before finish()).
  std::unique_ptr<Renderer> renderer;
  if (rendering) {
    renderer = make_renderer(o.gl);  // a GL failure shows up now
    if (std::max(grid->cell_width(), grid->cell_height()) > renderer->max_size())
      throw UsageError("--width/--height: tiles of " + std::to_string(grid->cell_width()) + "x" +
                       std::to_string(grid->cell_height()) + " exceed the renderer's limit of " +
                       std::to_string(renderer->max_size()) + " pixels");
  }
  PipelineConfig config;
  config.rendering = rendering;
  config.width = grid->cell_width();
  config.height = grid->cell_height();
  config.tiles = true;
  config.command = "compare";
  apply_look(look, config);
  config.scene_render = scene.render;
  if (look.camera_auto) config.camera = auto_camera(model, scene.render, static_cast<double>(config.width) / config.height);
  FramePipeline pipeline(model, targets, lanes, config, renderer.get());
  Composer composer{grid, {}};
  composer.labels = look.overlay == OverlayMode::None ? std::vector<std::string>(lanes.size())
                                                     : lane_tile_labels(lanes, *grid);
  if (!o.video.empty())
    pipeline.add(make_video_output(make_video_sink(o.video, VideoOptions{fps, o.crf, o.preset}), o.video, composer));
  if (!o.frames_dir.empty())
    for (std::size_t i = 0; i < lanes.size(); ++i)
      pipeline.add(make_frames_output(
          make_png_sequence_sink((fs::path(o.frames_dir) / lane_dirs[i]).string(),
                                 with_renderer(frame_metadata(model, lanes[i].kind, lanes[i].dt), *renderer)),
          i));
  const PngText meta = renderer ? with_renderer({{"scene", model.name}, {"software", "clothsim " CLOTHSIM_VERSION}}, *renderer)
                                : PngText{};
  if (o.still_t) pipeline.add(make_still_output(o.still_out, composer, meta));
  if (!o.sheet.empty()) {
    std::vector<std::string> rows, columns;
    for (const LaneSpec& l : lanes) rows.push_back(l.label());
    for (double t : sheet_times) columns.push_back(time_label(t));
    pipeline.add(make_sheet_output(o.sheet, rows, columns, meta, width, height));
  }

  // 3. Run it.
  const std::vector<std::string> after = o.summary.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.summary};
  const PipelineReport report = pipeline.run("compare " + model.name, after);

  // 4. The summary.
  print_summary(model, report, config.color);
  if (report.reference && report.reference->divergence) {
    // The error colouring measures nothing after it: say so where a user looks, with the fix.
    std::fflush(stdout);
    std::fprintf(stderr,
                 "clothsim: warning: the reference lane %s @ %s s diverged at t = %.6g s: the error colouring stops "
                 "there; give --reference NAME@STEP with a smaller step or a stabler method\n",
                 report.reference->spec.name().c_str(), report.reference->spec.step_text.c_str(),
                 report.reference->divergence->t);
  }
  double sim_cpu = 0.0;
  for (const LaneResult& r : report.lanes) sim_cpu += r.totals.cpu_seconds;
  if (report.reference) sim_cpu += report.reference->totals.cpu_seconds;
  if (!o.summary.empty()) {
    std::vector<JsonObject> lanes_json;
    for (std::size_t i = 0; i < report.lanes.size(); ++i) {
      JsonObject lane = lane_summary(model, report.lanes[i], "lane");
      if (config.color != FieldKind::None) with_field(lane, report, i);
      lanes_json.push_back(lane);
    }
    if (report.reference) lanes_json.push_back(lane_summary(model, *report.reference, "reference"));
    JsonObject extra;
    extra.text("color", std::string(field_kind_name(config.color)));
    if (report.color_range && rendering)  // (a summary alone draws nothing: no scale)
      extra.number("color_range_lo", report.color_range->lo).number("color_range_hi", report.color_range->hi);
    write_summary(o.summary, "compare", scene.source, lanes_json, extra);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
  if (!quiet()) {
    std::string outputs;
    for (const auto& [what, seconds] : report.output_seconds) {
      char buf[64];
      std::snprintf(buf, sizeof buf, ", %s %.1f s", what.c_str(), seconds);
      outputs += buf;
    }
    std::fprintf(stderr,
                 "compare: %ld time%s, %dx%d (%zu tiles of %dx%d), in %.1f s wall: simulate %.1f s cpu "
                 "on %zu threads (the renderer waited %.1f s), render %.1f s%s\n",
                 report.targets, report.targets == 1 ? "" : "s", grid->width(), grid->height(), lanes.size(), grid->cell_width(), grid->cell_height(),
                 wall, sim_cpu, lanes.size() + (report.reference ? 1 : 0), report.wait_seconds, report.render_seconds,
                 outputs.c_str());
  }
  return kOk;
}

}  // namespace

void add_compare_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* sub = app.add_subcommand(
      "compare",
      "Run one scene with several integrators (or one at several steps) at once and show them side by\n"
      "side: a tiled, labelled MP4 (--video), each lane's PNGs (--frames), a contact sheet (--sheet),\n"
      "and a summary table of cost and divergence on stdout. By default each tile is coloured by its\n"
      "error against a reference lane (RK4 at a quarter of the smallest step, or at its predicted\n"
      "stable step if smaller) and shows its force evaluations. Divergence is a result here (exit 0).\n"
      "Without --video or --frames, the lanes stop at the last --times or --still (at 1 s at least when\n"
      "the colour scale is taken from the first second's data; --color-range LO,HI avoids that).\n"
      "Beneath the table, each lane's field in numbers, with the frames they cover.");
  add_scene_options(sub, o->scene, /*single_run=*/false);
  add_gl_options(sub, o->gl);
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  add_picture_look_options(sub, o->look, /*compare=*/true);
  sub->add_option("--summary", o->summary, "Write what each lane did as JSON (docs/summary.md)")->type_name("FILE.json");
  sub->add_option("--integrators", o->integrators,
                  "Lanes, one tile each: NAME[@STEP],... (rk4@1e-4,rk4@4e-4,implicit_euler@1/60; the same integrator\n"
                  "may appear at several steps; without @STEP, --dt or the scene's dt), or course: the course's four\n"
                  "(explicit Euler, the one-iteration fixed-point implicit, midpoint, RK4); implicit_euler_fixed_point[@STEP]\n"
                  "is the course's implicit alone")
      ->capture_default_str();
  sub->add_option("--layout", o->layout,
                  "COLUMNSxROWS: 2x2, 4x1 (side by side), 1x4 (stacked), Nx1, 1xN or auto")
      ->capture_default_str();
  sub->add_option("--video", o->video, "Write the tiled clip as H.264 MP4")->type_name("FILE.mp4");
  sub->add_option("--frames", o->frames_dir,
                  "Keep every lane's PNGs in DIR/<integrator>/frame_00000.png... (DIR/<integrator>@<step>/ when an\n"
                  "integrator has several lanes)")
      ->type_name("DIR");
  sub->add_option("--dt", o->dt,
                  "Step for the lanes without @STEP: all (S), per integrator (rk4=2e-4,implicit_euler=1/60) or "
                  "both (1e-4,rk4=2e-4); a number or a fraction of a second; default: the scene's dt")
      ->type_name("S|NAME=S,...");
  sub->add_option("--sheet", o->sheet, "Write a contact sheet: one row per lane, one column per --times")
      ->type_name("FILE.png");
  sub->add_option("--times", o->times, "Contact-sheet columns, simulated seconds, increasing")
      ->type_name("T1,T2,...");
  sub->add_option("--still", o->still_t, "Write the tiled picture at time T (s) to -o/--output")->type_name("T");
  sub->add_option("-o,--output,--out", o->still_out, "PNG file for --still")->type_name("FILE.png");
  add_picture_options(sub, o->scene, "the whole grid", "--frames and --video");
  sub->add_option("--crf", o->crf, "Video quality, x264 CRF 0 (lossless) .. 51")->capture_default_str();
  sub->add_option("--preset", o->preset, "x264 preset (ultrafast .. veryslow)")->capture_default_str();
  sub->callback([o, &command] { command = [o] { return compare_command(*o); }; });
}

}  // namespace clothsim::cli
