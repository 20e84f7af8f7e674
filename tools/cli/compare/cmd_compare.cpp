// clothsim compare SCENE [--integrators NAME[@STEP],... | course] [--layout auto] [--video FILE.mp4]
//                        [--frames DIR] [--export PATH] [--dt S | --dt name=S,...] [--duration S] [--set K=V]...
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
// By default the lanes are matched on cost (step_matching.h: each free lane at the step where
// its work per simulated second equals the cheapest lane's at the scene's step) and the tiles
// coloured by each particle's distance from a reference lane (RK4 at a quarter of the smallest
// step, or at its predicted stable step where that is smaller: fit_reference_to_model) run
// alongside and never shown, on one logarithmic scale whose colour bar is drawn once, in a
// strip beside the grid (grid_legend.h); each tile shows its work and CPU time, and a lane
// that is finite but implausible is marked WRONG (plausibility.h): what each method buys for
// the same cost, on screen.
//
// The command reads as its phases: plan (check everything, build the model, choose the
// steps), outputs (the pipeline and what it feeds), run, report.
//
// Outputs are checked before any simulation (unknown integrator or layout, unwritable
// paths, bad --dt or --times: milliseconds, exit 2 or 1), created without a name and
// named when complete. SIGINT / SIGTERM stop every lane before its next step, drop the incomplete
// outputs and exit 130 / 143 saying what stays: the files of --frames and --export written so far.
//
// Frame k is the state at t = k / fps for k = 0 .. floor(duration * fps), as in `run`.
// The summary (stdout) has one row per lane (and the reference's); the time breakdown
// (stderr) says where the wall time went.
#include <algorithm>
#include <chrono>
#include <deque>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compare_plan.h"
#include "compare_shard.h"
#include "compare_summary.h"
#include "step_matching.h"
#include "cli/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/gl_options.h"
#include "cli/common/lanes.h"
#include "cli/common/memory_budget.h"
#include "cli/common/progress.h"
#include "cli/common/scene_options.h"
#include "cli/common/summary_json.h"
#include "cli/frames/export_output.h"
#include "cli/frames/frame_pipeline.h"
#include "cli/frames/frame_sink.h"
#include "cli/frames/grid_legend.h"
#include "cli/frames/picture_options.h"
#include "cli/frames/pipeline_outputs.h"
#include "cli/run/run_outputs.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/echo.h"
#include "scene/param_keys.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "study/reference.h"
#include "video/tiling.h"
#include "video/video_writer.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct CompareOptions {
  SceneOptions scene;
  std::string integrators = default_comparison_list();  // the course's four, by name
  std::string layout = "auto";
  std::string video, frames_dir, dt, sheet, times, still_out, export_path;
  std::optional<double> still_t;
  std::vector<std::string> match{"cost"};  // --match cost | error TOL | none
  std::string vary;                         // --vary KEY=V1,V2,...
  bool integrators_given = false;           // --integrators on the command line (a --vary grid's rows)
  bool match_given = false;                 // --match on the command line (--vary matches only when asked)
  int crf = VideoOptions{}.crf;
  std::string preset = VideoOptions{}.preset;
  GlOptions gl;
  PictureOptions look;
  std::string summary;  // --summary FILE.json
  std::string shard;    // --shard K/N|auto, with --frames only (compare_shard.h)
};

// Everything compare does, worked out and checked before any lane runs.
struct ComparePlan {
  SceneDef scene;
  std::vector<LaneSpec> lanes;
  SummaryContext context;  // the lanes' names and how their steps were chosen
  GridLayout layout;
  PictureLook look;
  bool with_frames = false, rendering = false;
  std::vector<double> sheet_times;
  std::optional<TileGrid> grid;
  int legend_width = 0;  // the colour bar's strip right of the grid (grid_legend.h)
  std::optional<TargetPlan> targets;
  std::vector<std::string> lane_dirs;
  std::optional<Model> model;
  // --vary: per value, its scene and model (a deque: the pipeline keeps pointers), and per
  // lane the model it runs; the tiles' labels ("ks = 2e4", or "rk4  ks = 2e4" in a grid).
  std::vector<SceneDef> vary_scenes;
  std::deque<Model> vary_models;
  std::vector<const Model*> lane_models;
  std::vector<std::string> labels;
  std::vector<std::string> values;  // per lane: its value's label alone ("ks = 2e4")
  std::optional<LaneSpec> error_reference;  // --match error: the reference the steps were matched against
  // The error colouring's reference, started before the steps are matched (start_reference_early;
  // it reads model and targets, so the plan never moves, and is declared last: stopped first).
  std::shared_ptr<LaneWorker> early_reference;
};

// --vary draws no error colouring (each value is its own scene, with no one reference): strain
// unless --color says otherwise.
PictureOptions look_options(const CompareOptions& o) {
  PictureOptions look = o.look;
  if (!o.vary.empty() && !look.color) look.color = "strain";
  if (!o.vary.empty() && look.color == "error")
    throw UsageError("--color error: --vary runs a scene per value, with no one reference to measure against; "
                     "use --color strain, speed or checker");
  return look;
}

// The options that go together, and an output to write, before the scene is read.
void check_option_pairs(const CompareOptions& o) {
  if (o.sheet.empty() != o.times.empty())
    throw UsageError(o.sheet.empty() ? "--times goes with --sheet FILE.png"
                                     : "--sheet needs --times T1,T2,... (the columns)");
  if (!o.vary.empty() && !o.match.empty() && o.match.front() == "error")
    throw UsageError("--match error: --vary runs a scene per value, with no one reference to match against; "
                     "use --match cost or none");
  if (o.still_t.has_value() != !o.still_out.empty())
    throw UsageError(o.still_t ? "--still needs -o/--output FILE.png" : "-o/--output goes with --still T");
  // A comparison that writes nothing would simulate every lane for nothing (the table it
  // prints is also in --summary): refused before any work.
  if (o.video.empty() && o.frames_dir.empty() && o.sheet.empty() && !o.still_t && o.summary.empty() && o.export_path.empty())
    throw UsageError("nothing to write: give --video FILE.mp4, --frames DIR, --sheet FILE.png, "
                     "--still T -o FILE.png, --export PATH or --summary FILE.json");
  try {
    validate_video_options(VideoWriterOptions{30.0, o.crf, o.preset});
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--video: ") + e.what());
  }
}

// The pictures' look; a summary alone draws none.
PictureLook resolve_look(const CompareOptions& o, const ComparePlan& p) {
  PictureLook look = resolve_picture_look(look_options(o), p.scene, p.lanes, /*compare=*/true);
  if (!o.vary.empty()) look.reference.reset();  // a scene per value: the inset shows E - E(0)
  if (p.rendering) return look;
  // The field is measured only when --color asks for it (the default reference, RK4 at a
  // quarter step, costs several times the lanes); its scale is then not chosen.
  if (o.look.color && look.color != FieldKind::None) {
    if (!look.color_range) look.color_range = ColorRange{1e-6, 1e-3};
    return look;
  }
  if (look.color != FieldKind::None && !o.summary.empty() && !quiet())
    std::fprintf(stderr, "compare: no pictures, so no %s measured; --color %s puts it in the summary\n",
                 std::string(field_kind_name(look.color)).c_str(), std::string(field_kind_name(look.color)).c_str());
  return PictureLook{};
}

void check_paths(const CompareOptions& o, const ComparePlan& p) {
  std::vector<PathRole> outputs{{o.video, "--video"}, {o.sheet, "--sheet"}, {o.still_out, "-o/--output"},
                                {o.summary, "--summary"}, {o.frames_dir, "--frames", true}};
  for (PathRole& r : export_roles(o.export_path, p.lane_dirs, static_cast<int>(p.scene.spheres.size())))
    outputs.push_back(std::move(r));
  refuse_clashing_paths({{o.scene.path, "the scene"}}, outputs);
  if (!o.video.empty()) require_writable_parent(o.video, "--video");
  if (!o.sheet.empty()) require_writable_parent(o.sheet, "--sheet");
  if (!o.still_out.empty()) require_writable_parent(o.still_out, "-o/--output");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  if (!o.frames_dir.empty() && fs::exists(o.frames_dir) && !fs::is_directory(o.frames_dir))
    throw RuntimeFailure("cannot write --frames into " + o.frames_dir + ": not a directory");
  for (const std::string& d : o.frames_dir.empty() ? std::vector<std::string>{} : p.lane_dirs)
    refuse_existing_frames((fs::path(o.frames_dir) / d).string(), "--frames");
  checked_export_paths(o.export_path, p.lane_dirs, static_cast<int>(p.scene.spheres.size()));
}

// The grid within the picture.
void fit_grid(ComparePlan& p) {
  try {  // the whole picture's: the tiles and, when coloured, the colour bar's strip
    const LegendGrid fitted = fit_legend_grid(p.layout, p.scene.render.width, p.scene.render.height,
                                              p.rendering ? p.look.color : FieldKind::None);
    p.grid.emplace(fitted.grid);
    p.legend_width = fitted.legend_width;
  } catch (const LayoutError& e) {
    throw UsageError(std::string("--width/--height: ") + e.what());
  }
}

// Whether the error's reference may start before the steps are chosen (start_reference_early).
bool starts_reference_early(const CompareOptions& o, const PictureLook& look) {
  return parse_match(o.match).kind != MatchKind::Error && look.color == FieldKind::Error && look.reference;
}

// Peak memory, estimated and checked before the renderer or the encoder exist: one Model (and
// a copy per fixed-point lane), a run per lane and the reference, the renderer at tile size,
// the tiles, the grid, the PNG writers' queues (3 tiles each), the contact sheet's cells, the
// first second held for the colour scale, and the encoder.
void check_memory(const CompareOptions& o, const ComparePlan& p) {
  const SceneDef& scene = p.scene;
  const int particles = scene.cloth.nx * scene.cloth.ny;
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  for (const SceneDef& s : p.vary_scenes) budget.add("model for --vary", model_bytes(s));
  for (const LaneSpec& l : p.lanes)
    budget.add(l.spelling(), run_bytes(scene, l.kind) + kLaneThreadBytes + (l.fixed_point ? model_bytes(scene) : 0.0));
  if (p.look.reference && p.look.color == FieldKind::Error) {
    budget.add("reference " + p.look.reference->name(), run_bytes(scene, p.look.reference->kind) + kLaneThreadBytes);
    std::vector<double> steps;
    for (const LaneSpec& l : p.lanes) steps.push_back(l.dt);
    budget.add("reference positions at the lanes' times",
               reference_positions_bytes(scene, steps, *p.targets, reference_queue_capacity(particles, steps)));
  }
  if (p.look.reference && p.look.inset_energy && p.look.color != FieldKind::Error)  // else the error's run
    budget.add("reference for the energy inset", run_bytes(scene, p.look.reference->kind) + kLaneThreadBytes);
  if (starts_reference_early(o, p.look))
    budget.add("reference states kept while the steps are chosen",
               static_cast<double>(reference_ahead_states(particles)) * final_state_bytes(scene, p.look.reference->kind));
  const TileGrid& grid = *p.grid;
  if (p.rendering) {
    const double n = static_cast<double>(p.lanes.size());
    const int width = grid.width() + p.legend_width;
    const double tile = 4.0 * grid.cell_width() * grid.cell_height(), canvas = 4.0 * width * grid.height();
    budget.add("renderer and images " + std::to_string(width) + "x" + std::to_string(grid.height()),
               kRendererBytes + render_bytes(grid.cell_width(), grid.cell_height(), p.look.samples) + n * tile +
                   2.0 * canvas + (o.frames_dir.empty() ? 0.0 : 3.0 * n * tile));
    if (!o.sheet.empty()) budget.add("contact sheet", 2.0 * n * static_cast<double>(p.sheet_times.size()) * tile);
    if (p.look.color != FieldKind::None && !p.look.color_range)
      budget.add("the first second, held for the colour scale",
                 held_frames_bytes(scene, p.lanes.size(), std::min(1.0, scene.duration) * scene.render.fps + 1.0));
  }
  if (!o.video.empty()) budget.add("encoder", encoder_bytes(grid.width() + p.legend_width, grid.height()));
  budget.check(scene.source, o.scene.max_memory);
}

// Which --vary lanes may have their step chosen: those of a row (an integrator) that is free,
// every value of it.
std::vector<bool> vary_free_lanes(const CompareOptions& o, const ComparePlan& p) {
  const std::string rows = o.integrators_given ? o.integrators : std::string(integrator_name(p.scene.integrator));
  const std::vector<bool> row_free = free_lanes(rows, o.dt, p.scene.dt);
  std::vector<bool> free;
  for (std::size_t i = 0; i < p.lanes.size(); ++i) free.push_back(row_free[i / p.vary_scenes.size()]);
  return free;
}

// The lanes' steps by --match (step_matching.h), and their names. --vary compares the values at
// one step unless --match is given; matched on cost, each lane's cost is measured on its own scene.
void choose_steps(const CompareOptions& o, ComparePlan& p) {
  if (!o.vary.empty() && !o.match_given) {
    p.context.step_choice.assign(p.lanes.size(), "the lane's step (--vary compares the values at one step)");
    return;
  }
  const MatchRequest match = parse_match(o.match);
  const std::vector<bool> free = o.vary.empty() ? free_lanes(o.integrators, o.dt, p.scene.dt) : vary_free_lanes(o, p);
  const MatchClip clip{p.scene.duration, p.scene.render.fps, p.scene.dt};
  const LaneSpec reference = parse_reference(o.look.reference, p.lanes);
  p.context.step_choice = match_steps(*p.model, p.lanes, free, match, clip, reference, p.lane_models);
  if (match.kind == MatchKind::Error) p.error_reference = error_reference(reference, clip.fps);
}

// The sheet's and the still's times within the run, and the targets: what every lane and the
// reference stop at, known before any step is chosen.
void plan_targets(const CompareOptions& o, ComparePlan& p, const PictureLook& look) {
  p.sheet_times = o.sheet.empty() ? std::vector<double>{} : parse_times(o.times, p.scene.duration);
  if (o.still_t && !(*o.still_t >= 0.0 && *o.still_t <= p.scene.duration + 1e-9))
    throw UsageError("--still: " + number_text(*o.still_t) + " s is outside the run (0 to " +
                     number_text(p.scene.duration) + " s)");
  p.targets.emplace(p.scene.duration, p.scene.render.fps, p.with_frames, p.sheet_times, o.still_t.value_or(-1.0));
  if (look.color != FieldKind::None && !look.color_range) p.targets->with_scale_window(kColorScaleWindow);
}

// The error colouring's reference, started at once on the core the pilots of --match cost
// leave idle: its step is a quarter of the smallest lane step, which matching on cost leaves as
// it is (the cheapest lane keeps the scene's step; the others cost more a step and take larger
// ones). It runs ahead until the pipeline gives it the lanes' steps; keep_early_reference
// drops it should matching change it after all. Not under --match error (another reference).
void start_reference_early(const CompareOptions& o, ComparePlan& p, PictureLook look) {
  if (!starts_reference_early(o, look) || (look.reference_is_default && analysis::smooth_scene(*p.model))) return;
  try {
    fit_reference_to_model(look, *p.model, p.scene, p.lanes);
  } catch (const UsageError&) {
    return;  // said after matching, if it still holds
  }
  if (!run_bounds_problem(p.scene.duration, look.reference->dt, p.scene.render.fps).empty()) return;
  LaneNeeds needs;
  needs.stand_for_later = true;
  p.early_reference = std::make_shared<LaneWorker>(*p.model, *look.reference, *p.targets, needs, kLaneQueueCapacity,
                                                   [] { return interrupted(); });
}

// The early reference, kept only if it is the run the matched lanes' reference is.
void keep_early_reference(ComparePlan& p) {
  if (!p.early_reference) return;
  if (p.look.color != FieldKind::Error || !p.look.reference || !same_run(p.early_reference->spec(), *p.look.reference))
    p.early_reference.reset();  // stops it
}

// The rows' names: the --vary labels where there are, else each lane's name.
void name_lanes(ComparePlan& p) {
  p.context.names.clear();
  for (std::size_t i = 0; i < p.lanes.size(); ++i)
    p.context.names.push_back(p.lanes[i].name() + (p.values.empty() ? "" : ", " + p.values[i]));
}

// --vary KEY=V1,V2,...: a scene per value (the user's --set, then the key's), and the lanes
// repeated per value: one integrator (the scene's, or --integrators' rows) x the values.
void plan_variation(const CompareOptions& o, ComparePlan& p) {
  const Variation vary = parse_vary(o.vary, p.scene);
  const std::vector<LaneSpec> rows =
      o.integrators_given ? p.lanes : parse_lanes(std::string(integrator_name(p.scene.integrator)), o.dt, p.scene.dt);
  for (std::size_t v = 0; v < vary.size(); ++v) {
    SceneOptions with = o.scene;
    for (const std::string& set : vary.sets(v)) with.sets.push_back(set);
    p.vary_scenes.push_back(load_scene_with_options(with));  // a bad value: the parser's message names it
  }
  p.lanes.clear();
  p.lane_dirs.clear();
  const std::vector<std::string> row_dirs = lane_directories(rows);
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t v = 0; v < vary.size(); ++v) {
      p.lanes.push_back(rows[r]);
      const std::string label = vary.label(v);
      p.labels.push_back(rows.size() > 1 ? rows[r].name() + "  " + label : label);
      p.values.push_back(label);
      std::string dir = row_dirs[r] + "_" + label;
      dir.erase(std::remove(dir.begin(), dir.end(), ' '), dir.end());
      p.lane_dirs.push_back(dir);
    }
}

// A --vary grid: a column per value, a row per integrator.
std::string grid_layout_text(const ComparePlan& p) {
  const std::size_t columns = p.vary_scenes.size();
  return std::to_string(columns) + "x" + std::to_string(p.lanes.size() / columns);
}

// 1. Everything that can be wrong, before any simulation; the steps chosen (the error's
// reference running meanwhile). In place: the reference started reads the plan's model and targets.
void plan_compare(const CompareOptions& o, ComparePlan& p) {
  check_option_pairs(o);
  p.scene = load_scene_with_options(o.scene);
  p.lanes = parse_lanes(o.integrators, o.dt, p.scene.dt);
  parse_match(o.match);  // a bad --match before any pilot runs
  p.with_frames = !o.video.empty() || !o.frames_dir.empty() || !o.export_path.empty();
  p.rendering = !o.video.empty() || !o.frames_dir.empty() || !o.sheet.empty() || o.still_t;  // not --export
  p.lane_dirs = lane_directories(p.lanes);
  if (!o.vary.empty()) plan_variation(o, p);
  try {
    p.layout = parse_layout(o.layout == "auto" && !o.vary.empty() ? grid_layout_text(p) : o.layout,
                            static_cast<int>(p.lanes.size()));
  } catch (const LayoutError& e) {
    throw UsageError(std::string("--layout: ") + e.what());
  }
  check_paths(o, p);                                 // an output that is an input, before anything is said
  const PictureLook unmatched = resolve_look(o, p);  // bad --color, --camera, ... before any pilot runs
  plan_targets(o, p, unmatched);
  p.look = unmatched;  // the memory a run needs is the same whatever steps matching chooses
  fit_grid(p);
  check_memory(o, p);  // before the models, the pilots and the early reference take any
  p.model.emplace(build_model(p.scene));
  for (const SceneDef& s : p.vary_scenes) p.vary_models.push_back(build_model(s));
  if (!p.vary_models.empty())  // lanes row by row, a value per column
    for (std::size_t i = 0; i < p.lanes.size(); ++i) p.lane_models.push_back(&p.vary_models[i % p.vary_models.size()]);
  start_reference_early(o, p, unmatched);
  choose_steps(o, p);
  name_lanes(p);
  p.look = resolve_look(o, p);
  // Tiles matched on error are coloured against the reference they were matched against, so
  // the clip's numbers and the match agree (the default's quarter of the smallest matched step
  // would be another run, and on a scene with contacts no two references agree to the bit).
  if (p.error_reference && p.look.reference && p.look.reference_is_default) {
    p.look.reference = p.error_reference;
    p.look.reference_is_default = false;
  }  // the reference's step follows the lanes'
  check_step_bounds(p.scene, p.lanes, p.look.reference);
  fit_grid(p);
  check_memory(o, p);  // again with the steps chosen (the reference's positions per distinct step)
  if (!o.sheet.empty())
    check_sheet_fits(p.grid->cell_width(), p.grid->cell_height(), sheet_rows(p.lanes, p.labels),
                     static_cast<int>(p.sheet_times.size()), p.grid->width(), p.grid->height());
  fit_reference_to_model(p.look, *p.model, p.scene, p.lanes);
  keep_early_reference(p);
}

PipelineConfig pipeline_config(const ComparePlan& p) {
  PipelineConfig config;
  config.rendering = p.rendering;
  config.width = p.grid->cell_width();
  config.height = p.grid->cell_height();
  config.tiles = true;
  config.judge = true;
  config.lane_models = p.lane_models;
  config.command = "compare";
  apply_look(p.look, config);
  if (p.look.inset_energy) config.energy_reference = p.look.reference;  // E - E_ref (none under --vary)
  config.started_reference = p.early_reference;
  config.scene_render = p.scene.render;
  if (p.look.camera_auto)
    config.camera = auto_camera(*p.model, p.scene.render, static_cast<double>(config.width) / config.height);
  return config;
}

// 2. The outputs the pipeline feeds (each removes its temporary if destroyed before finish()).
void add_outputs(const CompareOptions& o, const ComparePlan& p, FramePipeline& pipeline, Renderer* renderer) {
  const Model& model = *p.model;
  Composer composer{p.grid, {}, p.legend_width};
  composer.labels = p.look.overlay == OverlayMode::None ? std::vector<std::string>(p.lanes.size())
                    : p.labels.empty()                  ? lane_tile_labels(p.lanes, *p.grid)
                                                        : p.labels;
  if (!o.video.empty())
    pipeline.add(make_video_output(make_video_sink(o.video, VideoOptions{p.scene.render.fps, o.crf, o.preset}), o.video,
                                   composer));
  if (!o.frames_dir.empty())
    for (std::size_t i = 0; i < p.lanes.size(); ++i)
      pipeline.add(make_frames_output(
          make_png_sequence_sink((fs::path(o.frames_dir) / p.lane_dirs[i]).string(),
                                 with_renderer(frame_metadata(model, p.lanes[i].kind, p.lanes[i].dt), *renderer)),
          i));
  const PngText meta = renderer ? with_renderer({{"scene", model.name}, {"software", "clothsim " CLOTHSIM_VERSION}}, *renderer)
                                : PngText{};
  if (o.still_t) pipeline.add(make_still_output(o.still_out, composer, meta));
  add_export_outputs(pipeline, export_paths(o.export_path, p.lane_dirs), model, p.lane_models, p.scene.render.fps,
                     p.look.color == FieldKind::Error);
  if (!o.sheet.empty()) {
    std::vector<std::string> columns;
    for (double t : p.sheet_times) columns.push_back(time_label(t));
    pipeline.add(make_sheet_output(o.sheet, sheet_rows(p.lanes, p.labels), columns, meta, p.grid->width() + p.legend_width, p.grid->height(),
                                   p.legend_width > 0));
  }
}

std::unique_ptr<Renderer> make_checked_renderer(const CompareOptions& o, const ComparePlan& p) {
  if (!p.rendering) return nullptr;
  std::unique_ptr<Renderer> renderer = make_renderer(o.gl);  // a GL failure shows up now
  if (std::max(p.grid->cell_width(), p.grid->cell_height()) > renderer->max_size())
    throw UsageError("--width/--height: tiles of " + std::to_string(p.grid->cell_width()) + "x" +
                     std::to_string(p.grid->cell_height()) + " exceed the renderer's limit of " +
                     std::to_string(renderer->max_size()) + " pixels");
  return renderer;
}

// The time breakdown on stderr: where the wall time went.
// 4. The table, the warnings, the JSON and the breakdown.
void report_compare(const CompareOptions& o, const ComparePlan& p, const PipelineReport& report, FieldKind color,
                    Clock::time_point wall_start) {
  print_summary(*p.model, report, color, p.context);
  if (report.reference && report.reference->divergence) {
    // The error colouring measures nothing after it: say so where a user looks, with the fix.
    std::fflush(stdout);
    std::fprintf(stderr,
                 "clothsim: warning: the reference lane %s @ %s s diverged at t = %.6g s: the error colouring stops "
                 "there; give --reference NAME@STEP with a smaller step or a stabler method\n",
                 report.reference->spec.name().c_str(), report.reference->spec.step_text.c_str(),
                 report.reference->divergence->t);
  }
  if (!o.summary.empty()) {
    JsonObject extra;
    extra.text("color", std::string(field_kind_name(color)));
    extra.text("match", o.match.front() + (o.match.size() > 1 ? " " + o.match[1] : ""));
    if (report.color_range && p.rendering)  // (a summary alone draws nothing: no scale)
      extra.number("color_range_lo", report.color_range->lo).number("color_range_hi", report.color_range->hi);
    if (color == FieldKind::Error && report.reference) extra.object("reference", summary_reference(report));
    write_summary(o.summary, "compare", p.scene.source, summary_lanes(*p.model, report, color, p.context), extra);
  }
  if (!quiet())
    print_breakdown(*p.grid, p.legend_width, report, std::chrono::duration<double>(Clock::now() - wall_start).count());
}

// --shard: the plan of the whole comparison, narrowed to this part's lanes (compare_shard.h).
void keep_shard_lanes(const CompareOptions& o, ComparePlan& p) {
  const FramesShardPlan shard{o.shard, o.frames_dir, p.look.color != FieldKind::None && !p.look.color_range, p.scene.duration,
                              p.model->num_particles, p.targets->frames(), p.grid->cell_width(), p.grid->cell_height()};
  const std::vector<std::size_t> keep = frames_shard_lanes(shard, p.lanes, p.lane_dirs);
  const auto narrow = [&keep](auto& per_lane) {
    if (per_lane.empty()) return;
    std::remove_reference_t<decltype(per_lane)> kept;
    for (std::size_t i : keep) kept.push_back(per_lane[i]);
    per_lane = kept;
  };
  narrow(p.lanes), narrow(p.lane_dirs), narrow(p.lane_models), narrow(p.labels), narrow(p.values);
  narrow(p.context.names), narrow(p.context.step_choice);
}

int compare_command(const CompareOptions& o) {
  const auto wall_start = Clock::now();
  install_interrupt_handler();  // first: Ctrl-C during setup is then seen at the first frame
  if (!o.shard.empty())
    check_frames_shard_outputs(o.frames_dir, !o.video.empty() || !o.sheet.empty() || o.still_t || !o.summary.empty());
  ComparePlan p;
  plan_compare(o, p);
  if (!o.shard.empty()) keep_shard_lanes(o, p);
  if (p.lanes.empty()) return kOk;  // a part with no lane (more parts than lanes)
  const std::unique_ptr<Renderer> renderer = make_checked_renderer(o, p);
  const PipelineConfig config = pipeline_config(p);
  FramePipeline pipeline(*p.model, *p.targets, p.lanes, config, renderer.get());
  add_outputs(o, p, pipeline, renderer.get());
  const std::vector<std::string> after = o.summary.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.summary};
  const PipelineReport report = pipeline.run("compare " + p.model->name, after);  // 3. run it
  report_compare(o, p, report, config.color, wall_start);
  return kOk;
}

}  // namespace

void add_compare_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* sub = app.add_subcommand("compare",
      "Run one scene with several integrators (or one at several steps) at once and show them side by\n"
      "side: a tiled, labelled MP4 (--video), each lane's PNGs (--frames), a contact sheet (--sheet),\n"
      "and a summary table of cost and divergence on stdout. By default the lanes are matched on cost\n"
      "(--match), each tile is coloured by its error against a reference lane (RK4 at a quarter of the\n"
      "smallest step, or at its predicted stable step if smaller) and shows its work and CPU time, and a\n"
      "finite but implausible lane is marked WRONG. Divergence is a result here (exit 0).\n"
      "Without --video, --frames or --export, the lanes stop at the last --times or --still (at 1 s at least when\n"
      "the colour scale is taken from the first second's data; --color-range LO,HI avoids that).\n"
      "Beneath the table, each lane's field in numbers, with the frames they cover.");
  add_scene_options(sub, o->scene, /*single_run=*/false);
  add_gl_options(sub, o->gl);
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  add_picture_look_options(sub, o->look, /*compare=*/true);
  sub->add_option("--summary", o->summary, "Write what each lane did as JSON (docs/summary.md)")->type_name("FILE.json");
  add_frames_shard_option(sub, o->shard);
  sub->add_option("--integrators", o->integrators,
                  "Lanes, one tile each: NAME[@STEP],... (rk4@1e-4,rk4@4e-4,implicit_euler@1/60; the same integrator\n"
                  "may appear at several steps; without @STEP, --dt or the scene's dt), or course: the course's four\n"
                  "(explicit Euler, the one-iteration fixed-point implicit, midpoint, RK4); implicit_euler_fixed_point[@STEP]\n"
                  "is the course's implicit alone")
      ->capture_default_str();
  sub->add_option("--match", o->match,
                  "Each lane's step, for lanes without @STEP or --dt: cost (default: the step where its work per\n"
                  "simulated second, in spring-pass equivalents, equals the cheapest lane's at the scene's step), error TOL\n"
                  "(the largest step within TOL metres of the reference at every frame, by bisection) or none (the scene's)")
      ->expected(1, 2)
      ->type_name("cost|error TOL|none");
  sub->add_option("--vary", o->vary,
                  "Lanes by a parameter's value, labelled 'ks = 2e4': KEY a dotted scene path, a glob over the spring\n"
                  "types (cloth.springs.*.stiffness) or ks / kd (every spring type's stiffness / damping). With\n"
                  "--integrators, a grid: a row per integrator, a column per value; without, the scene's integrator.\n"
                  "The lanes run at one step unless --match cost is given; colour by strain unless --color says otherwise")
      ->type_name("KEY=V1,V2,...");
  sub->add_option("--layout", o->layout,
                  "COLUMNSxROWS: 2x2, 4x1 (side by side), 1x4 (stacked), Nx1, 1xN or auto")
      ->capture_default_str();
  sub->add_option("--video", o->video, "Write the tiled clip as H.264 MP4")->type_name("FILE.mp4");
  add_export_option(sub, o->export_path);
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
  sub->callback([o, sub, &command] {
    o->integrators_given = sub->get_option("--integrators")->count() > 0;
    o->match_given = sub->get_option("--match")->count() > 0;
    command = [o] { return compare_command(*o); };
  });
}

}  // namespace clothsim::cli
