// clothsim compare SCENE [--integrators a,b,c,d] [--layout auto] [--video FILE.mp4] [--frames DIR]
//                        [--dt S | --dt name=S,...] [--duration S] [--set K=V]...
//                        [--sheet FILE.png --times 0.5,1,2,4] [--still T --out FILE.png]
//                        [--width W --height H] [--crf Q] [--preset P]
//
// The scene is loaded once and built into one Model; one Run per integrator advances on
// its own thread (compare_runner.h) while this thread renders each run's snapshot into a
// tile, composes the tiles into a grid and streams it to the encoder. A run that diverges
// freezes on its last good frame with a DIVERGED banner while the others go on: in
// compare, divergence is a result (exit 0), shown in the clip and in the summary table.
//
// Outputs are checked before any simulation (unknown integrator or layout, unwritable
// paths, bad --dt or --times: milliseconds, exit 2 or 1), created without a name and
// named when complete. SIGINT / SIGTERM stop every run before its next step (the renderer
// never waits on a lane for more than 20 ms without looking), drop the incomplete outputs and
// exit 130 / 143 saying what stays: PNGs already written under --frames (each is complete).
//
// Frame k is the state at t = k / fps for k = 0 .. floor(duration * fps), as in `run`.
// The summary (stdout) has one row per run; the time breakdown (stderr) says where the
// wall time went: simulation (CPU time summed over the run threads, and how long the
// renderer waited for them), render, compose, PNG and encode on the main thread.
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

#include "cli_common.h"
#include "commands.h"
#include "compare_plan.h"
#include "compare_runner.h"
#include "contact_sheet.h"
#include "frame_sink.h"
#include "gl_options.h"
#include "summary_json.h"
#include "memory_budget.h"
#include "memory_estimate.h"
#include "png_io.h"
#include "renderer.h"
#include "run_bounds.h"
#include "run_outputs.h"
#include "scene_options.h"
#include "scene_parser.h"
#include "tiling.h"
#include "video_writer.h"

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
  std::string summary;  // --summary FILE.json
};

// Seconds spent in each stage on the main thread.
struct StageTimes {
  double wait = 0, render = 0, compose = 0, png = 0, encode = 0, sheet = 0;
};

class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), start_(Clock::now()) {}
  ~Stopwatch() { total_ += std::chrono::duration<double>(Clock::now() - start_).count(); }
 private:
  double& total_;
  Clock::time_point start_;
};

void print_summary(const Model& model, const std::vector<RunSummary>& runs) {
  std::printf("%s: %zu runs\n", model.name.c_str(), runs.size());
  std::printf("%-17s %10s %10s %13s %9s %14s  %s\n", "integrator", "dt_s", "steps", "force_evals",
              "cpu_s", "cpu_ms_per_s", "result");
  for (const RunSummary& r : runs) {
    // Cost per simulated second over the time actually simulated (up to divergence).
    const double simulated = r.divergence ? r.divergence->t : r.t;
    char result[192];
    if (r.divergence)
      std::snprintf(result, sizeof result, "DIVERGED at t = %.4g s: %s", r.divergence->t,
                    r.divergence->reason.c_str());
    else if (r.totals.unconverged_steps > 0)
      std::snprintf(result, sizeof result,
                    "NOT CONVERGED: %" PRId64 " of %" PRId64 " steps, max residual %.2g (to t = %.4g s)",
                    r.totals.unconverged_steps, r.totals.steps, r.totals.max_residual, r.t);
    else
      std::snprintf(result, sizeof result, "ok to t = %.4g s", r.t);
    std::printf("%-17s %10.3g %10" PRId64 " %13" PRId64 " %9.3f %14.1f  %s\n",
                std::string(integrator_name(r.kind)).c_str(), r.dt, r.totals.steps,
                r.totals.force_evals, r.totals.cpu_seconds, simulated > 0 ? 1e3 * r.totals.cpu_seconds / simulated : 0.0,
                result);
  }
  // What the implicit solve did, beside the table (0 for the explicit family, so not a column):
  // contacts it held as constraints, and particles the post-step projection still had to move.
  for (const RunSummary& r : runs)
    if (r.kind == IntegratorKind::ImplicitEuler)
      std::printf("%s: %" PRId64 " Newton and %" PRId64 " CG iterations (%" PRId64 " sparse factorizations), largest final residual %.2g; "
                  "contacts held in the solve %" PRId64 ", post-step projections %" PRId64 "\n",
                  std::string(integrator_name(r.kind)).c_str(), r.totals.newton_iterations,
                  r.totals.cg_iterations, r.totals.factorizations, r.totals.max_residual, r.totals.contact_constraints,
                  r.totals.safety_projections);
}

int compare_command(const CompareOptions& o) {
  const auto wall_start = Clock::now();
  install_interrupt_handler();  // first: Ctrl-C during setup is then seen at the first frame

  // 1. Everything that can be wrong, before any simulation.
  const std::vector<IntegratorKind> kinds = parse_integrator_list(o.integrators);
  GridLayout layout;
  try {
    layout = parse_layout(o.layout, static_cast<int>(kinds.size()));
  } catch (const LayoutError& e) {
    throw UsageError(std::string("--layout: ") + e.what());
  }
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
  if (!o.video.empty()) require_writable_parent(o.video, "--video");
  if (!o.sheet.empty()) require_writable_parent(o.sheet, "--sheet");
  if (!o.still_out.empty()) require_writable_parent(o.still_out, "-o/--output");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  if (!o.frames_dir.empty() && fs::exists(o.frames_dir) && !fs::is_directory(o.frames_dir))
    throw RuntimeFailure("cannot write --frames into " + o.frames_dir + ": not a directory");
  if (!o.frames_dir.empty())
    for (IntegratorKind kind : kinds)
      refuse_existing_frames((fs::path(o.frames_dir) / std::string(integrator_name(kind))).string(), "--frames");

  const SceneDef scene = load_scene_with_options(o.scene);
  const std::vector<double> dts = parse_dt_list(o.dt, kinds, scene.dt);
  for (std::size_t i = 0; i < kinds.size(); ++i) {  // each lane's steps, bounded like the scene's
    const std::string too_long = run_bounds_problem(scene.duration, dts[i], scene.render.fps);
    if (!too_long.empty()) throw UsageError("--dt (" + std::string(integrator_name(kinds[i])) + "): " + too_long);
  }
  const std::vector<double> sheet_times =
      o.sheet.empty() ? std::vector<double>{} : parse_times(o.times, scene.duration);
  if (o.still_t && !(*o.still_t >= 0.0 && *o.still_t <= scene.duration + 1e-9))
    throw UsageError("--still: " + std::to_string(*o.still_t) + " s is outside the run (0 to " +
                     std::to_string(scene.duration) + " s)");
  const int width = scene.render.width, height = scene.render.height;  // the whole grid's (--width/--height)
  std::optional<TileGrid> grid;
  try {
    grid.emplace(TileGrid::fit(layout, width, height));
  } catch (const LayoutError& e) {
    throw UsageError(std::string("--width/--height: ") + e.what());
  }
  const double fps = scene.render.fps;
  const bool with_frames = !o.video.empty() || !o.frames_dir.empty();
  const bool rendering = with_frames || !o.sheet.empty() || o.still_t;

  // Peak memory, estimated and checked before the Model, the renderer or the encoder exist:
  // one Model, a run per lane, the renderer at tile size, the tiles, the grid, the PNG
  // writers' queues (3 tiles each), the contact sheet's cells and the encoder.
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  for (IntegratorKind kind : kinds) budget.add(std::string(integrator_name(kind)), run_bytes(scene, kind));
  if (rendering) {
    const double lanes = static_cast<double>(kinds.size());
    const double tile = 4.0 * grid->cell_width() * grid->cell_height(), canvas = 4.0 * grid->width() * grid->height();
    budget.add("renderer and images " + std::to_string(grid->width()) + "x" + std::to_string(grid->height()),
               kRendererBytes + render_bytes(grid->cell_width(), grid->cell_height(), scene.render.samples) +
                   lanes * tile + canvas + (o.frames_dir.empty() ? 0.0 : 3.0 * lanes * tile));
    if (!o.sheet.empty())
      budget.add("contact sheet", 2.0 * lanes * static_cast<double>(sheet_times.size()) * tile);
  }
  if (!o.video.empty()) budget.add("encoder", encoder_bytes(grid->width(), grid->height()));
  budget.check(scene.source, o.scene.max_memory);
  const Model model = build_model(scene);
  const TargetPlan targets(scene.duration, fps, with_frames, sheet_times, o.still_t.value_or(-1.0));
  const long frames = targets.frames();

  // 2. Outputs (each removes its temporary if destroyed before finish()).
  std::unique_ptr<Renderer> renderer;
  if (rendering) {
    renderer = make_renderer(o.gl);  // a GL failure shows up now
    if (std::max(grid->cell_width(), grid->cell_height()) > renderer->max_size())
      throw UsageError("--width/--height: tiles of " + std::to_string(grid->cell_width()) + "x" +
                       std::to_string(grid->cell_height()) + " exceed the renderer's limit of " +
                       std::to_string(renderer->max_size()) + " pixels");
  }
  std::unique_ptr<FrameSink> video;
  if (!o.video.empty()) video = make_video_sink(o.video, VideoOptions{fps, o.crf, o.preset});
  std::vector<std::unique_ptr<FrameSink>> tile_pngs;
  if (!o.frames_dir.empty())
    for (std::size_t i = 0; i < kinds.size(); ++i)
      tile_pngs.push_back(make_png_sequence_sink(
          (fs::path(o.frames_dir) / std::string(integrator_name(kinds[i]))).string(),
          with_renderer(frame_metadata(model, kinds[i], dts[i]), *renderer)));

  // 3. The runs, one thread each, and the render/compose/encode loop on this thread.
  std::vector<std::unique_ptr<RunWorker>> workers;
  for (std::size_t i = 0; i < kinds.size(); ++i)
    workers.push_back(std::make_unique<RunWorker>(model, kinds[i], dts[i], targets, grid->cell_width(),
                                                  grid->cell_height(), 4, [] { return interrupted(); }));

  StageTimes time;
  std::vector<Image> tiles(kinds.size());
  std::vector<const Image*> tile_ptrs;
  for (const Image& tile : tiles) tile_ptrs.push_back(&tile);
  std::vector<bool> frozen(kinds.size(), false);
  // The integrator's name again, large, at each tile's bottom-left: the overlay text is
  // small at tile size, and a viewer should tell the tiles apart at a glance. The PNGs of
  // --frames stay unlabelled (`encode` labels them when it assembles a clip).
  std::vector<std::string> labels;
  for (IntegratorKind kind : kinds) labels.emplace_back(integrator_name(kind));
  std::vector<std::vector<Image>> sheet_cells(kinds.size(), std::vector<Image>(sheet_times.size()));
  Image canvas;
  auto progress = std::make_unique<Progress>("compare " + model.name, targets.size(), "frames");
  TileSnapshot snapshot;
  bool still_written = false;
  // A signal: the runs stop before their next step, every output not complete is dropped
  // (each sink removes its temporary), and the message says what stays on disk.
  const auto stop_here = [&](double t) -> RuntimeFailure {
    for (auto& w : workers) w->stop();
    progress.reset();
    std::vector<std::string> kept, lost;
    for (auto& sink : tile_pngs) {
      const std::string left = sink->abandon();
      if (!left.empty()) kept.push_back(left);
    }
    if (video) video->abandon();
    if (still_written) kept.push_back(o.still_out);
    for (const std::string* out : {&o.video, &o.sheet, &o.summary})
      if (!out->empty()) lost.push_back(*out);
    if (!o.still_out.empty() && !still_written) lost.push_back(o.still_out);
    return RuntimeFailure(interruption_message(t, kept, lost));
  };
  TargetPlan::Cursor cursor(targets);
  long n = 0;
  for (Target target; cursor.next(target); ++n) {
    if (interrupted()) throw stop_here(target.t);
    for (std::size_t i = 0; i < workers.size(); ++i) {
      if (frozen[i]) continue;  // a diverged run keeps its last picture
      {
        Stopwatch watch(time.wait);
        const bool got = workers[i]->next(snapshot);
        if (interrupted()) throw stop_here(target.t);  // next() gives up on a signal
        if (!got) continue;
      }
      frozen[i] = snapshot.frozen;
      if (rendering) {
        Stopwatch watch(time.render);
        tiles[i] = renderer->render(snapshot.frame);
      }
    }
    if (target.still) {
      Stopwatch watch(time.sheet);
      grid->compose(tile_ptrs, labels, canvas);
      write_png(o.still_out, canvas,
                with_renderer({{"scene", model.name}, {"t", std::to_string(target.t)},
                               {"software", "clothsim " CLOTHSIM_VERSION}}, *renderer));
      still_written = true;
    }
    if (target.frame >= 0) {
      for (std::size_t i = 0; i < tile_pngs.size(); ++i) {
        Stopwatch watch(time.png);
        tile_pngs[i]->add(target.frame, target.t, tiles[i]);
      }
      if (video) {
        {
          Stopwatch watch(time.compose);
          grid->compose(tile_ptrs, labels, canvas);
        }
        Stopwatch watch(time.encode);
        video->add(target.frame, target.t, canvas);
      }
    }
    if (target.column >= 0)
      for (std::size_t i = 0; i < tiles.size(); ++i) sheet_cells[i][target.column] = tiles[i];
    progress->update(n + 1);
  }
  progress.reset();

  // 4. Complete the outputs.
  for (auto& sink : tile_pngs) {
    Stopwatch watch(time.png);
    sink->finish();
  }
  if (video) {
    Stopwatch watch(time.encode);
    video->finish();
  }
  if (!o.sheet.empty()) {
    Stopwatch watch(time.sheet);
    std::vector<std::string> rows, columns;
    for (IntegratorKind kind : kinds) rows.emplace_back(integrator_name(kind));
    for (double t : sheet_times) columns.push_back(time_label(t));
    write_png(o.sheet, compose_contact_sheet(sheet_cells, rows, columns),
              with_renderer({{"scene", model.name}, {"software", "clothsim " CLOTHSIM_VERSION}}, *renderer));
  }

  std::vector<RunSummary> runs;
  double sim_cpu = 0.0;
  for (auto& w : workers) {
    w->join();
    runs.push_back(w->summary());
    sim_cpu += runs.back().totals.cpu_seconds;
  }
  print_summary(model, runs);
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
  if (!o.summary.empty()) {
    std::vector<JsonObject> lanes;
    for (const RunSummary& r : runs)
      lanes.push_back(lane_json(model.name, r.kind, r.dt, r.totals,
                                r.divergence ? std::optional<double>(r.divergence->t) : std::nullopt)
                          .number("t_reached", r.t));
    write_summary(o.summary, "compare", scene.source, lanes);
  }
  if (!quiet())
    std::fprintf(stderr,
               "compare: %ld frames of %dx%d (%zu tiles of %dx%d) in %.1f s wall: simulate %.1f s cpu "
               "on %zu threads (renderer waited %.1f s), render %.1f s, compose %.2f s, PNG %.1f s, "
               "encode %.1f s, sheet/still %.1f s\n",
               frames, grid->width(), grid->height(), kinds.size(), grid->cell_width(),
               grid->cell_height(), wall, sim_cpu, workers.size(), time.wait, time.render,
               time.compose, time.png, time.encode, time.sheet);
  return kOk;
}

}  // namespace

void add_compare_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* sub = app.add_subcommand(
      "compare",
      "Run one scene with several integrators at once and show them side by side: a tiled,\n"
      "labelled MP4 (--video), each run's PNGs (--frames), a contact sheet (--sheet), and a\n"
      "summary table of cost and divergence on stdout. Divergence is a result here (exit 0).\n"
      "Without --video or --frames, the runs stop at the last --times or --still.");
  add_scene_options(sub, o->scene, /*single_run=*/false);
  add_gl_options(sub, o->gl);
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  sub->add_option("--summary", o->summary, "Write what each run did as JSON (docs/summary.md)")->type_name("FILE.json");
  sub->add_option("--integrators", o->integrators, "Comma-separated integrators, one tile each")
      ->capture_default_str();
  sub->add_option("--layout", o->layout,
                  "COLUMNSxROWS: 2x2, 4x1 (side by side), 1x4 (stacked), Nx1, 1xN or auto")
      ->capture_default_str();
  sub->add_option("--video", o->video, "Write the tiled clip as H.264 MP4")->type_name("FILE.mp4");
  sub->add_option("--frames", o->frames_dir, "Keep every tile's PNGs in DIR/<integrator>/frame_00000.png...")
      ->type_name("DIR");
  sub->add_option("--dt", o->dt,
                  "Step for all runs (S), per run (rk4=2e-4,implicit_euler=1/60) or both "
                  "(1e-4,rk4=2e-4); a number or a fraction of a second; default: the scene's dt")
      ->type_name("S|NAME=S,...");
  sub->add_option("--sheet", o->sheet, "Write a contact sheet: one row per integrator, one column per --times")
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
