// compare's plan (compare_job.h): the phases of plan_compare, each a function below, then the
// pipeline's configuration and outputs. Moved from tools/cli/compare/cmd_compare.cpp as it was,
// with the lanes as one CompareLane each instead of parallel lists.
#include "compare_job.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compare_shard.h"
#include "step_matching.h"
#include "clip/common/cli_common.h"
#include "clip/common/memory_budget.h"
#include "clip/reference/reference_stand.h"  // reference_positions_bytes
#include "clip/common/progress.h"
#include "clip/frames/export_output.h"
#include "clip/frames/grid_legend.h"
#include "clip/frames/pipeline_outputs.h"
#include "clip/frames/reference_record.h"
#include "clip/frames/run_outputs.h"
#include "render/png_io.h"
#include "scene/build_model.h"
#include "scene/echo.h"
#include "scene/memory_estimate.h"
#include "scene/param_keys.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "study/reference.h"
#include "render/video/video_writer.h"

namespace clothsim::clip {

std::vector<Lane> ComparePlan::specs() const {
  std::vector<Lane> out;
  for (const CompareLane& l : lanes) out.push_back(l.spec);
  return out;
}

std::vector<std::string> ComparePlan::dirs() const {
  std::vector<std::string> out;
  for (const CompareLane& l : lanes) out.push_back(l.dir);
  return out;
}

std::vector<const Model*> ComparePlan::models() const {
  if (vary_models.empty()) return {};
  std::vector<const Model*> out;
  for (const CompareLane& l : lanes) out.push_back(l.model);
  return out;
}

std::vector<std::string> ComparePlan::labels() const {
  if (vary_scenes.empty()) return {};
  std::vector<std::string> out;
  for (const CompareLane& l : lanes) out.push_back(l.label);
  return out;
}

SummaryContext ComparePlan::summary_context() const {
  SummaryContext c;
  for (const CompareLane& l : lanes) {
    c.names.push_back(l.name);
    c.step_choice.push_back(l.step_choice);
  }
  return c;
}

namespace {

namespace fs = std::filesystem;

// --vary colours by strain unless --color says otherwise: each value is its own scene, so
// --color error runs a reference per value (variant_references), the cost of one more lane each.
PictureOptions look_options(const CompareRequest& o) {
  PictureOptions look = o.look;
  if (!o.vary.empty() && !look.color) look.color = "strain";
  return look;
}

// The options that go together, and an output to write, before the scene is read.
void check_option_pairs(const CompareRequest& o) {
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
  if (o.video.empty() && o.frames_dir.empty() && o.sheet.empty() && !o.still_t && o.summary.empty() && o.export_path.empty() &&
      !o.table_wanted)
    throw UsageError("nothing to write: give --video FILE.mp4, --frames DIR, --sheet FILE.png, "
                     "--still T -o FILE.png, --export PATH or --summary FILE.json");
  try {
    validate_video_options(VideoWriterOptions{30.0, o.crf, o.preset});
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--video: ") + e.what());
  }
}

// The pictures' look; a summary alone draws none.
PictureLook resolve_look(const CompareRequest& o, const ComparePlan& p) {
  PictureLook look = resolve_picture_look(look_options(o), p.scene, p.specs(), /*compare=*/true);
  // A scene per value: the inset shows E - E(0); the error, each value's own reference.
  if (!o.vary.empty() && look.color != FieldKind::Error) look.reference.reset();
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

void check_paths(const CompareRequest& o, const ComparePlan& p) {
  std::vector<PathRole> outputs{{o.video, "--video"}, {o.sheet, "--sheet"}, {o.still_out, "-o/--output"},
                                {o.summary, "--summary"}, {o.frames_dir, "--frames", true}};
  for (PathRole& r : export_roles(o.export_path, p.dirs(), static_cast<int>(p.scene.spheres.size())))
    outputs.push_back(std::move(r));
  refuse_clashing_paths({{o.scene.path, "the scene"}}, outputs);
  if (!o.video.empty()) require_writable_parent(o.video, "--video");
  if (!o.sheet.empty()) require_png_name(o.sheet, "--sheet");
  if (!o.sheet.empty()) require_writable_parent(o.sheet, "--sheet");
  if (!o.still_out.empty()) require_png_name(o.still_out, "-o/--output");
  if (!o.still_out.empty()) require_writable_parent(o.still_out, "-o/--output");
  if (!o.summary.empty()) require_writable_parent(o.summary, "--summary");
  if (!o.frames_dir.empty() && fs::exists(o.frames_dir) && !fs::is_directory(o.frames_dir))
    throw RuntimeFailure("cannot write --frames into " + o.frames_dir + ": not a directory");
  for (const std::string& d : o.frames_dir.empty() ? std::vector<std::string>{} : p.dirs())
    refuse_existing_frames((fs::path(o.frames_dir) / d).string(), "--frames");
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

// Peak memory, estimated and checked before the renderer or the encoder exist: one Model (a
// lane's settings ride in its run: no lane copies it), a run per lane and the reference, the
// renderer at tile size, the tiles, the grid, the PNG writers' queues (3 tiles each), the
// contact sheet's cells, the first second held for the colour scale, and the encoder.
void check_memory(const CompareRequest& o, const ComparePlan& p) {
  const SceneDef& scene = p.scene;
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  for (const SceneDef& s : p.vary_scenes) budget.add("model for --vary", model_bytes(s));
  for (const CompareLane& lane : p.lanes) {
    const Lane& l = lane.spec;
    budget.add(l.spelling(), run_bytes(scene, l.kind) + kLaneThreadBytes);
  }
  // The error's reference, or under --vary one per value (each its value's model and run).
  const std::size_t references = p.vary_scenes.empty() ? 1 : p.vary_scenes.size();
  for (std::size_t k = 0; p.look.reference && p.look.color == FieldKind::Error && k < references; ++k) {
    const std::string which = references > 1 ? " for " + p.lanes[k].value : "";
    const SceneDef& of = p.vary_scenes.empty() ? scene : p.vary_scenes[k];  // a value may change the sheet
    budget.add("reference " + p.look.reference->name() + which, run_bytes(of, p.look.reference->kind) + kLaneThreadBytes);
    // Its check (reference_stand.h, study/reference.h): a run at twice its step, or the looser
    // adaptive solve on a thread of its own.
    budget.add("reference check" + which, run_bytes(of, p.look.reference->kind) + kLaneThreadBytes);
    std::vector<double> steps;
    for (const CompareLane& l : p.lanes) steps.push_back(l.spec.landing_grid());
    const int served = of.cloth.nx * of.cloth.ny;
    budget.add("reference positions at the lanes' times" + which,
               reference_positions_bytes(of, steps, *p.targets, reference_queue_capacity(served, steps)));
    if (analysis::ReferenceCache(p.look.reference_cache).enabled())  // what it serves, kept until it is stored (reference_record.h)
      budget.add("reference frames held for the cache" + which, reference_record_bytes(served, steps, p.targets->size()));
  }
  if (p.look.reference && p.look.inset_energy && p.look.color != FieldKind::Error)  // else the error's run
    budget.add("reference for the energy inset", run_bytes(scene, p.look.reference->kind) + kLaneThreadBytes);
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
  if (!o.export_path.empty())  // each lane's queued bodies and mesh (counted whole per lane: a bound)
    budget.add("export of " + std::to_string(p.lanes.size()) + " lanes",
               static_cast<double>(p.lanes.size()) * export_bytes(scene, parse_export_path(o.export_path).format));
  budget.check(scene.source, o.scene.max_memory);
}

// The lanes' steps by --match (step_matching.h), and their names. --vary compares the values at
// one step unless --match is given; matched on cost, each lane's cost is measured on its own scene.
void choose_steps(const CompareRequest& o, ComparePlan& p) {
  if (!o.vary.empty() && !o.match_given) {
    for (CompareLane& l : p.lanes) l.step_choice = "the lane's step (--vary compares the values at one step)";
    return;
  }
  const MatchRequest match = parse_match(o.match);
  const MatchClip clip{p.scene.duration, p.scene.render.fps, p.scene.dt};
  std::vector<Lane> specs = p.specs();
  const Lane reference = parse_reference(o.look.reference, specs);
  const std::vector<std::string> choices = match_steps(*p.model, specs, match, clip, reference, p.models());
  for (std::size_t i = 0; i < p.lanes.size(); ++i) {
    p.lanes[i].spec = specs[i];
    p.lanes[i].step_choice = choices[i];
  }
  if (match.kind == MatchKind::Error) p.error_reference = error_reference(reference, clip.fps);
}

// The sheet's and the still's times within the run, and the targets: what every lane and the
// reference stop at, known before any step is chosen.
void plan_targets(const CompareRequest& o, ComparePlan& p, const PictureLook& look) {
  p.sheet_times = o.sheet.empty() ? std::vector<double>{} : parse_times(o.times, p.scene.duration);
  if (o.still_t && !(*o.still_t >= 0.0 && *o.still_t <= p.scene.duration + 1e-9))
    throw UsageError("--still: " + number_text(*o.still_t) + " s is outside the run (0 to " +
                     number_text(p.scene.duration) + " s)");
  // Rows for a front end end where its lanes do: at the duration, a whole frame or not.
  auto targets = std::make_shared<TargetPlan>(p.scene.duration, p.scene.render.fps, p.with_frames, p.sheet_times,
                                              o.still_t.value_or(-1.0), /*to_end=*/o.frame_rows_wanted);
  if (look.color != FieldKind::None && !look.color_range) targets->with_scale_window(kColorScaleWindow);
  p.targets = std::move(targets);
}

// The rows' names: the --vary labels where there are, else each lane's name.
void name_lanes(ComparePlan& p) {
  for (CompareLane& l : p.lanes) l.name = l.spec.name() + (l.value.empty() ? "" : ", " + l.value);
}

// --vary KEY=V1,V2,...: a scene per value (the user's --set, then the key's), and the lanes
// repeated per value: one integrator (the scene's, or --integrators' rows) x the values.
void plan_variation(const CompareRequest& o, ComparePlan& p) {
  const Variation vary = parse_vary(o.vary, p.scene);
  for (const std::string& path : vary.key.paths)  // what every lane of one clip shares: one value or none
    if (path == "duration" || path == "name" || path.rfind("render.", 0) == 0 || path == "render")
      throw UsageError("--vary " + vary.key.label + ": every lane of one comparison shares the scene's " + path +
                       " (one clip, one picture); give it with --set or its own option, one compare per value");
  std::vector<Lane> rows =
      o.integrators_given ? p.specs() : parse_lanes(std::string(integrator_name(p.scene.integrator)), o.dt, p.scene.dt);
  follow_scene_solver(rows, p.scene.implicit);  // the scene's fixed point is named as itself, as without --vary
  for (std::size_t v = 0; v < vary.size(); ++v) {
    SceneOptions with = o.scene;
    for (const std::string& set : vary.sets(v)) with.sets.push_back(set);
    try {  // a bad key or value: the parser's message, said of --vary as typed
      p.vary_scenes.push_back(load_scene_with_options(with));
    } catch (const SceneError& e) {
      throw as_option_error(e, vary.key, "--vary " + o.vary);
    }
  }
  p.lanes.clear();
  const std::vector<std::string> row_dirs = lane_directories(rows);
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t v = 0; v < vary.size(); ++v) {
      CompareLane lane;
      lane.spec = rows[r];
      lane.value = vary.label(v);
      lane.label = rows.size() > 1 ? rows[r].name() + "  " + lane.value : lane.value;
      lane.dir = row_dirs[r] + "_" + lane.value;
      lane.dir.erase(std::remove(lane.dir.begin(), lane.dir.end(), ' '), lane.dir.end());
      p.lanes.push_back(std::move(lane));
    }
}

// --vary --color error: per value, the reference fitted to its own model (a smooth value gets
// the adaptive solve, a value with projected contacts RK4 within its own stable step) over its
// own lanes' steps.
void fit_variant_references(ComparePlan& p) {
  if (p.vary_models.empty() || p.look.color != FieldKind::Error || !p.look.reference) return;
  const std::size_t values = p.vary_models.size();
  for (std::size_t v = 0; v < values; ++v) {
    std::vector<Lane> specs;
    for (std::size_t i = v; i < p.lanes.size(); i += values) specs.push_back(p.lanes[i].spec);
    PictureLook look = p.look;
    fit_reference_to_model(look, p.vary_models[v], p.vary_scenes[v], specs);
    check_step_bounds(p.vary_scenes[v], specs, look.reference);
    p.variant_references.push_back({&p.vary_models[v], *look.reference, look.reference_tolerance, p.lanes[v].value});
  }
}

// A --vary grid: a column per value, a row per integrator.
std::string grid_layout_text(const ComparePlan& p) {
  const std::size_t columns = p.vary_scenes.size();
  return std::to_string(columns) + "x" + std::to_string(p.lanes.size() / columns);
}

}  // namespace

ComparePlan plan_compare(const CompareRequest& o) {
  ComparePlan p;
  check_option_pairs(o);
  p.scene = load_scene_with_options(o.scene);
  std::vector<Lane> specs = parse_lanes(o.integrators, o.dt, p.scene.dt);
  follow_scene_solver(specs, p.scene.implicit);  // --set implicit.solver=fixed_point: named as itself
  const std::vector<std::string> dirs = lane_directories(specs);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    CompareLane lane;
    lane.spec = specs[i];
    lane.dir = dirs[i];
    p.lanes.push_back(std::move(lane));
  }
  parse_match(o.match);  // a bad --match before any pilot runs
  p.with_frames = !o.video.empty() || !o.frames_dir.empty() || !o.export_path.empty() || o.frame_rows_wanted;
  p.rendering = !o.video.empty() || !o.frames_dir.empty() || !o.sheet.empty() || o.still_t;  // not --export
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
  check_memory(o, p);  // before the models and the pilots take any
  // The export's folders, made by its checks once the run is admitted (a refused one leaves none).
  checked_export_paths(o.export_path, p.dirs(), static_cast<int>(p.scene.spheres.size()));
  p.model = std::make_shared<const Model>(build_model(p.scene));
  for (const SceneDef& s : p.vary_scenes) p.vary_models.push_back(build_model(s));
  if (!p.vary_models.empty())  // lanes row by row, a value per column
    for (std::size_t i = 0; i < p.lanes.size(); ++i) p.lanes[i].model = &p.vary_models[i % p.vary_models.size()];
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
  check_step_bounds(p.scene, p.specs(), p.look.reference);
  fit_grid(p);
  check_memory(o, p);  // again with the steps chosen (the reference's positions per distinct step)
  if (!o.sheet.empty())
    check_sheet_fits(p.grid->cell_width(), p.grid->cell_height(), sheet_rows(p.specs(), p.labels()),
                     static_cast<int>(p.sheet_times.size()), p.grid->width(), p.grid->height());
  fit_reference_to_model(p.look, *p.model, p.scene, p.specs());
  fit_variant_references(p);
  return p;
}

PipelineConfig pipeline_config(const ComparePlan& p) {
  PipelineConfig config;
  config.rendering = p.rendering;
  config.width = p.grid->cell_width();
  config.height = p.grid->cell_height();
  config.tiles = true;
  config.judge = true;
  config.lane_models = p.models();
  config.command = "compare";
  apply_look(p.look, config);
  if (p.look.inset_energy && p.vary_models.empty()) config.energy_reference = p.look.reference;  // E - E_ref
  config.variant_references = p.variant_references;
  config.scene_render = p.scene.render;
  if (p.look.camera_auto)
    config.camera = auto_camera(*p.model, p.scene.render, static_cast<double>(config.width) / config.height);
  return config;
}

void add_outputs(const CompareRequest& o, const ComparePlan& p, FramePipeline& pipeline, Renderer* renderer) {
  const Model& model = *p.model;
  Composer composer{p.grid, {}, p.legend_width};
  const std::vector<std::string> labels = p.labels();
  composer.labels = p.look.overlay == OverlayMode::None ? std::vector<std::string>(p.lanes.size())
                    : labels.empty()                    ? lane_tile_labels(p.specs(), *p.grid)
                                                        : labels;
  if (!o.video.empty())
    pipeline.add(make_video_output(make_video_sink(o.video, VideoOptions{p.scene.render.fps, o.crf, o.preset}), o.video,
                                   composer));
  if (!o.frames_dir.empty())
    for (std::size_t i = 0; i < p.lanes.size(); ++i)
      pipeline.add(make_frames_output(
          make_png_sequence_sink((fs::path(o.frames_dir) / p.lanes[i].dir).string(),
                                 with_renderer(frame_metadata(model, p.lanes[i].spec.kind, p.lanes[i].spec.dt), *renderer)),
          i));
  const PngText meta = renderer ? with_renderer({{"scene", model.name}, {"software", "clothsim " CLOTHSIM_VERSION}}, *renderer)
                                : PngText{};
  if (o.still_t) pipeline.add(make_still_output(o.still_out, composer, meta));
  add_export_outputs(pipeline, export_paths(o.export_path, p.dirs()), model, p.models(), p.scene.render.fps,
                     p.look.color == FieldKind::Error);
  if (!o.sheet.empty()) {
    std::vector<std::string> columns;
    for (double t : p.sheet_times) columns.push_back(time_label(t));
    pipeline.add(make_sheet_output(o.sheet, sheet_rows(p.specs(), p.labels()), columns, meta, p.grid->width() + p.legend_width, p.grid->height(),
                                   p.legend_width > 0));
  }
}

std::unique_ptr<Renderer> make_checked_renderer(const CompareRequest& o, const ComparePlan& p) {
  if (!p.rendering) return nullptr;
  std::unique_ptr<Renderer> renderer = make_renderer(o.gl);  // a GL failure shows up now
  if (std::max(p.grid->cell_width(), p.grid->cell_height()) > renderer->max_size())
    throw UsageError("--width/--height: tiles of " + std::to_string(p.grid->cell_width()) + "x" +
                     std::to_string(p.grid->cell_height()) + " exceed the renderer's limit of " +
                     std::to_string(renderer->max_size()) + " pixels");
  return renderer;
}

void keep_shard_lanes(const CompareRequest& o, ComparePlan& p) {
  const FramesShardPlan shard{o.shard, o.frames_dir, p.look.color != FieldKind::None && !p.look.color_range, p.scene.duration,
                              p.model->num_particles, p.targets->frames(), p.grid->cell_width(), p.grid->cell_height()};
  std::vector<CompareLane> kept;
  for (std::size_t i : frames_shard_lanes(shard, p.specs(), p.dirs())) kept.push_back(p.lanes[i]);
  p.lanes = std::move(kept);
}

std::optional<ComparePlan> plan_compare_part(const CompareRequest& o) {
  if (!o.shard.empty())
    check_frames_shard_outputs(o.frames_dir, !o.video.empty() || !o.sheet.empty() || o.still_t || !o.summary.empty());
  ComparePlan p = plan_compare(o);
  if (!o.shard.empty()) keep_shard_lanes(o, p);
  if (p.lanes.empty()) return std::nullopt;
  return p;
}

PipelineReport run_compare(const CompareRequest& o, const ComparePlan& p, std::vector<LaneFrameRow>* rows) {
  const std::unique_ptr<Renderer> renderer = make_checked_renderer(o, p);
  FramePipeline pipeline(*p.model, *p.targets, p.specs(), pipeline_config(p), renderer.get());
  add_outputs(o, p, pipeline, renderer.get());
  if (rows) pipeline.add(make_frame_rows_output(*rows, p.targets->duration()));
  const std::vector<std::string> after = o.summary.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.summary};
  return pipeline.run("compare " + p.model->name, after);
}

std::vector<JsonObject> compare_lanes_json(const ComparePlan& p, const PipelineReport& report) {
  return summary_lanes(*p.model, report, p.look.color, p.summary_context());
}

void write_compare_summary(const CompareRequest& o, const ComparePlan& p, const PipelineReport& report) {
  const FieldKind color = p.look.color;
  JsonObject extra;
  extra.text("color", std::string(field_kind_name(color)));
  extra.text("match", o.match.front() + (o.match.size() > 1 ? " " + o.match[1] : ""));
  if (report.color_range && p.rendering)  // (a summary alone draws nothing: no scale)
    extra.number("color_range_lo", report.color_range->lo).number("color_range_hi", report.color_range->hi);
  if (color == FieldKind::Error && report.references.size() == 1 && report.references[0].label.empty())
    extra.object("reference", summary_reference(report.references[0]));
  if (color == FieldKind::Error && !p.vary_models.empty()) {  // a reference per --vary value
    std::vector<JsonObject> references;
    for (const ReferenceReport& ref : report.references) references.push_back(summary_reference(ref));
    extra.array("references", references);
  }
  write_summary(o.summary, "compare", p.scene.source, compare_lanes_json(p, report), extra);
}

}  // namespace clothsim::clip
