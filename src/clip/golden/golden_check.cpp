#include "golden_check.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "clip/common/cli_common.h"
#include "clip/common/lanes.h"
#include "clip/common/memory_budget.h"
#include "clip/frames/run_budget.h"
#include "clip/compare/compare_job.h"
#include "clip/studies/study_common.h"
#include "render/png_io.h"
#include "scene/build_model.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "study/journal.h"
#include "study/work_precision.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

namespace fs = std::filesystem;

// Where a failed check leaves its evidence: "drape_t1500ms.png" -> "drape_t1500ms.actual.png".
std::string evidence_path(const GoldenOptions& o, const std::string& golden, const char* kind) {
  const fs::path g(golden);
  const fs::path dir = o.failures_dir.empty() ? g.parent_path() : fs::path(o.failures_dir);
  return (dir / (g.stem().string() + "." + kind + ".png")).string();
}

// Compares one render with its golden image, writing the evidence of a mismatch.
namespace {
// Why a golden that exists cannot be compared, before decoding it ("" when it may be): not a
// regular file, or a Git LFS pointer (the common CI case: cloned without `git lfs pull`).
std::string unreadable_golden(const std::string& golden) {
  if (!fs::is_regular_file(golden)) return "unreadable golden: not a regular file";
  std::ifstream in(golden, std::ios::binary);
  std::string head(64, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.rfind("version https://git-lfs", 0) == 0)
    return "unreadable golden: a Git LFS pointer, not the image (run `git lfs pull`)";
  return "";
}
}  // namespace

GoldenVerdict check_one(const GoldenOptions& o, const std::string& golden, const Image& actual, const DiffTolerance& tol,
                        std::vector<std::string>& evidence) {
  GoldenVerdict v;
  v.image = fs::path(golden).filename().string();
  v.threshold = tol.pixel_threshold;
  const std::string actual_path = evidence_path(o, golden, "actual"), diff_path = evidence_path(o, golden, "diff");
  if (!fs::exists(golden)) {
    v.problem = "missing (`clothsim golden update` writes it)";
  } else if (const std::string why = unreadable_golden(golden); !why.empty()) {
    v.problem = why;  // its own FAIL row: the other goldens are still checked
  } else {
    // The size from the header first: a golden of another size is never decoded (a huge one
    // would otherwise take memory the budget did not count). A golden that does not decode
    // (truncated, a bad CRC or IDAT) is this image's FAIL, not the check's end.
    PngSize size{};
    Image expected;
    try {
      size = read_png_size(golden);
      if (size.width == actual.width && size.height == actual.height) expected = read_png(golden);
    } catch (const PngError& e) {
      v.problem = std::string("unreadable golden: ") + e.what();
    }
    if (!v.problem.empty()) {
    } else if (size.width != actual.width || size.height != actual.height) {
      v.problem = "golden is " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                  ", the render " + std::to_string(actual.width) + "x" + std::to_string(actual.height);
    } else {
      const DiffStats stats = compare_images(expected, actual, tol.pixel_threshold);
      v.rms = stats.rms;
      v.max = stats.max;
      v.over_fraction = stats.over_fraction;
      if (within_tolerance(stats, tol)) {
        v.ok = true;
        fs::remove(actual_path);  // evidence of an earlier failure no longer holds
        fs::remove(diff_path);
        return v;
      }
      char text[160];
      std::snprintf(text, sizeof text, "rms %.3f (tolerance %g), max %d, %.3f%% past %d (tolerance %g%%)",
                    stats.rms, tol.max_rms, stats.max, 100.0 * stats.over_fraction, tol.pixel_threshold,
                    100.0 * tol.max_over_fraction);
      v.problem = text;
      write_png(diff_path, diff_image(expected, actual));
      evidence.push_back(diff_path);
      v.diff = diff_path;
    }
  }
  write_png(actual_path, actual);
  evidence.push_back(actual_path);
  v.actual = actual_path;
  return v;
}

namespace {

// Checks (or writes) the picture at each of an entry's times as the pipeline reaches it.
class GoldenOutput final : public FrameOutput {
 public:
  GoldenOutput(const GoldenOptions& o, const GoldenManifest& manifest, std::size_t entry, bool update,
               const Model& model, const Renderer& renderer, GoldenWork& work)
      : o_(o), manifest_(manifest), index_(entry), entry_(manifest.entries[entry]), update_(update), model_(model),
        renderer_(renderer), work_(work) {}
  std::string what() const override { return "golden"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.column < 0) return;
    const double t = entry_.times[static_cast<std::size_t>(target.column)];
    const std::string golden = golden_image_path(manifest_, entry_, t);
    const LaneFrame& f = *lanes.front().frame;
    if (f.divergence) {  // this image and the later ones of the entry cannot be made
      char problem[400];
      std::snprintf(problem, sizeof problem, "%s diverged at t = %.6g s: %s", entry_.scene.c_str(), f.divergence->t,
                    f.divergence->reason.c_str());
      GoldenVerdict v;
      v.image = fs::path(golden).filename().string();
      v.threshold = entry_.tolerance.pixel_threshold;
      v.problem = problem;
      report(v, t);
      return;
    }
    if (update_) {
      // Into a nameless file held until every image is made (written through /proc/self/fd).
      work_.staged.push_back(std::make_unique<OutputFile>(golden));
      write_png(work_.staged.back()->reopen_path(), *lanes.front().image,
                with_renderer({{"scene", model_.name}, {"integrator", std::string(integrator_name(lanes.front().spec->kind))},
                               {"t", std::to_string(t)}, {"software", "clothsim " CLOTHSIM_VERSION}},
                              renderer_));
    } else {
      report(check_one(o_, golden, *lanes.front().image, entry_.tolerance, work_.evidence), t);
    }
  }
  void finish() override {}
  void abandon(std::vector<std::string>& kept, std::vector<std::string>& lost) override {
    if (update_) {
      lost.push_back("every golden image (update writes all or none)");
    } else {
      kept.insert(kept.end(), work_.evidence.begin(), work_.evidence.end());
    }
  }
 private:
  void report(GoldenVerdict v, double t) {
    v.entry = index_;
    v.t = t;
    for (char& c : v.problem)
      if (c == '\n' || c == '\r') c = ' ';  // one CSV row, one report line
    std::printf("%s\n", golden_report_line(v).c_str());
    work_.bad += v.ok ? 0 : 1;
    work_.verdicts.push_back(v);
  }
  const GoldenOptions& o_;
  const GoldenManifest& manifest_;
  std::size_t index_;
  const GoldenEntry& entry_;
  bool update_;
  const Model& model_;
  const Renderer& renderer_;
  GoldenWork& work_;
};

}  // namespace

// Every scene is read, and its run's memory estimated, before any rendering, so a bad one
// fails at once (exit 2).
void load_entries(const GoldenOptions& o, const GoldenManifest& manifest, std::vector<SceneDef>& scenes,
                  std::vector<PictureLook>& looks) {
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const GoldenEntry& e = manifest.entries[i];
    const std::string key = "goldens[" + std::to_string(i) + "]";
    // Named against the manifest's line: the scene it points at, and times the run has (as
    // `run --still` refuses a time past the scene's duration).
    if (!fs::is_regular_file(e.scene))
      throw SceneError(manifest.path, e.line, key + ".scene", "not a scene file (missing, or a directory): " + e.scene);
    scenes.push_back(load_scene_within(e.scene, {}, o.max_memory));
    if (e.integrator) scenes.back().integrator = *e.integrator;
    if (e.dt) scenes.back().dt = *e.dt;
    if (e.dt && !e.times.empty()) {  // the parser bounded the scene's own dt; the run goes to the latest still
      const double latest = *std::max_element(e.times.begin(), e.times.end());
      const std::string too_long = run_bounds_problem(latest, *e.dt, scenes.back().render.fps);
      if (!too_long.empty()) throw SceneError(manifest.path, e.dt_line ? e.dt_line : e.line, key + ".dt", too_long);
    }
    for (std::size_t k = 0; k < e.times.size(); ++k)
      if (e.times[k] > scenes.back().duration + 1e-9) {
        char what[160];
        std::snprintf(what, sizeof what, "%g s is past the scene's duration (%g s): the run has no picture there",
                      e.times[k], scenes.back().duration);
        throw SceneError(manifest.path, e.times_line ? e.times_line : e.line,
                         key + ".times[" + std::to_string(k) + "]", what);
      }
    const SceneDef& scene = scenes.back();
    if (e.compare) {
      // Its lanes checked now (compare checks its memory when it plans each still).
      try {
        parse_lanes(e.integrators.empty() ? default_comparison_list() : e.integrators, "", scene.dt);
      } catch (const UsageError& error) {
        throw SceneError(manifest.path, e.line, key + ".integrators", error.what());
      }
      looks.emplace_back();
      continue;
    }
    // The pictures `run --still` makes (the frame pipeline with one lane: the scene's camera,
    // colouring and overlay), and the peak memory of that run at the entry's size: entries run
    // one after another, so each is held to --max-memory on its own.
    const Lane lane{scene.integrator, scene.dt, step_string(scene.dt), false};
    looks.push_back(resolve_picture_look({}, scene, {lane}, /*compare=*/false));
    run_budget(scene, looks.back(), {/*rendering=*/true, e.width, e.height, /*video=*/false})
        .check(manifest.path + (e.line > 0 ? ":" + std::to_string(e.line) : "") + ": " + key + " (" + e.scene + ")",
               o.max_memory);
  }
}

namespace {

// A kind: compare entry: per time, the grid `compare SCENE --integrators LANES --still T`
// draws at the entry's size (its lanes matched on cost, tiles and legend as compare makes
// them), into a nameless file, then checked or staged as a still's image is. Returns the
// first lane's run, the entry's lane in --summary.
LaneResult run_compare_entry(const GoldenOptions& o, const GoldenManifest& manifest, std::size_t i, const Model& model,
                             const Renderer& renderer, bool update, GoldenWork& work) {
  const GoldenEntry& e = manifest.entries[i];
  LaneResult first;
  for (const double t : e.times) {
    CompareRequest r;
    r.scene.path = e.scene;
    r.scene.width = e.width;
    r.scene.height = e.height;
    r.scene.dt = e.dt;
    r.scene.max_memory = o.max_memory;
    if (!e.integrators.empty()) r.integrators = e.integrators, r.integrators_given = true;
    r.still_t = t;
    r.gl = o.gl;
    const fs::path scratch = fs::temp_directory_path() / ("clothsim-golden-" + std::to_string(::getpid()));
    fs::create_directories(scratch);
    r.still_out = (scratch / "still.png").string();
    const ComparePlan plan = plan_compare(r);
    const PipelineReport report = run_compare(r, plan);
    if (first.totals.steps == 0 && !report.lanes.empty()) first = report.lanes.front().result;
    const Image image = read_png(r.still_out);
    fs::remove_all(scratch);
    const std::string golden = golden_image_path(manifest, e, t);
    if (update) {
      work.staged.push_back(std::make_unique<OutputFile>(golden));
      write_png(work.staged.back()->reopen_path(), image,
                with_renderer({{"scene", model.name}, {"integrators", r.integrators}, {"t", std::to_string(t)},
                               {"software", "clothsim " CLOTHSIM_VERSION}},
                              renderer));
      continue;
    }
    GoldenVerdict v = check_one(o, golden, image, e.tolerance, work.evidence);
    v.entry = i;
    v.t = t;
    std::printf("%s\n", golden_report_line(v).c_str());
    work.bad += v.ok ? 0 : 1;
    work.verdicts.push_back(v);
  }
  return first;
}

}  // namespace

// An entry's run, as run --still makes its pictures: each time a contact sheet's column,
// checked (or staged) as the pipeline reaches it. Returns the run's lane (totals, divergence).
LaneResult run_entry(const GoldenOptions& o, const GoldenManifest& manifest, std::size_t i, const SceneDef& scene,
                     const PictureLook& entry_look, const Model& model, Renderer& renderer, bool update,
                     GoldenWork& work, const std::vector<std::string>& not_written) {
  const GoldenEntry& e = manifest.entries[i];
  if (e.compare) return run_compare_entry(o, manifest, i, model, renderer, update, work);
  const Lane lane{scene.integrator, scene.dt, step_string(scene.dt), false};
  PictureLook look = entry_look;
  fit_reference_to_model(look, model, scene, {lane});  // as run does
  PipelineConfig config;
  config.rendering = true;
  config.width = e.width;
  config.height = e.height;
  config.stop_when_all_frozen = true;
  config.command = "golden";
  apply_look(look, config);
  config.scene_render = scene.render;
  if (look.camera_auto) config.camera = auto_camera(model, scene.render, static_cast<double>(e.width) / e.height);
  TargetPlan targets(*std::max_element(e.times.begin(), e.times.end()), scene.render.fps,
                     /*with_frames=*/false, e.times);
  if (look.color != FieldKind::None) targets.with_scale_window(kColorScaleWindow);
  FramePipeline pipeline(model, targets, {lane}, config, &renderer);
  pipeline.add(std::make_unique<GoldenOutput>(o, manifest, i, update, model, renderer, work));
  return pipeline.run("golden " + model.name, not_written).lanes.front().result;
}

// An entry in the summary: its run as a lane (the common keys), its name and its images.
JsonObject entry_lane_json(const GoldenEntry& e, std::size_t i, const SceneDef& scene, const Model& model,
                           const LaneResult& r, const std::vector<GoldenVerdict>& verdicts) {
  std::vector<JsonObject> images;
  for (const GoldenVerdict& v : verdicts)
    if (v.entry == i) images.push_back(golden_image_json(v));
  JsonObject lane = lane_json(model.name, scene.integrator, scene.dt, r.totals,
                              r.divergence ? std::optional<double>(r.divergence->t) : std::nullopt);
  lane.integer("entry", static_cast<std::int64_t>(i)).text("name", e.name).array("images", images);
  return lane;
}

// An entry's estimated cost in particle-force-evaluations: its run to the latest time and
// its pictures, a pixel counted as kPixelCost of them (docs/cluster.md).
double entry_cost(const GoldenEntry& e, const SceneDef& scene) {
  const double latest = *std::max_element(e.times.begin(), e.times.end());
  const double run = analysis::cost_estimate(scene.integrator, latest, scene.dt) * scene.cloth.nx * scene.cloth.ny;
  return run + kPixelCost * static_cast<double>(e.times.size()) * e.width * e.height;
}

// What a part of the check is a part of: every entry's scene bytes and settings.
ShardPlan golden_plan(const GoldenOptions& o, const GoldenManifest& manifest, const std::vector<SceneDef>& scenes) {
  ShardPlan plan{"golden", o.manifest, {}, "failures " + o.failures_dir, o.manifest, golden_csv_header(), {}};
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const GoldenEntry& e = manifest.entries[i];
    plan.plan += ";" + e.scene + " " + analysis::hash_text(analysis::read_whole_file(e.scene)) + " " + e.name + " " +
                 std::string(integrator_name(scenes[i].integrator)) + " " + csv_number(scenes[i].dt) + " " +
                 std::to_string(e.width) + "x" + std::to_string(e.height);
    for (double t : e.times) plan.plan += " " + csv_number(t);
    plan.costs.push_back(entry_cost(e, scenes[i]));
  }
  return plan;
}

// check's --csv and --summary, once every entry ran.
void write_check_outputs(const GoldenOptions& o, const GoldenManifest& manifest, const std::vector<JsonObject>& lanes,
                         const std::vector<double>& seconds, const GoldenWork& work) {
  if (!o.junit.empty()) {
    std::vector<std::string> names;
    for (const GoldenEntry& e : manifest.entries) names.push_back(e.name);
    AtomicFile file(o.junit);
    std::fputs(golden_junit(o.manifest, names, seconds, work.verdicts).c_str(), file.stream());
    file.commit();
  }
  if (!o.csv.empty()) {
    AtomicFile file(o.csv);
    std::fprintf(file.stream(), "%s\n", golden_csv_header().c_str());
    for (const GoldenVerdict& v : work.verdicts) std::fputs(golden_csv_row(v).c_str(), file.stream());
    file.commit();
  }
  if (!o.summary.empty()) write_summary(o.summary, "golden", o.manifest, lanes, golden_summary_keys(work.verdicts));
}

// A name whose image (or its evidence, NAME_tT.actual.png) is longer than the file system
// takes fails at the first write: refused at its key before any render.
void check_name_lengths(const GoldenOptions& o, const GoldenManifest& manifest) {
  for (std::size_t i = 0; i < manifest.entries.size(); ++i)
    for (double t : manifest.entries[i].times) {
      const fs::path p(evidence_path(o, golden_image_path(manifest, manifest.entries[i], t), "actual"));
      const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
      const long most = ::pathconf(fs::is_directory(dir) ? dir.c_str() : ".", _PC_NAME_MAX);
      const std::size_t length = p.filename().string().size();
      if (most > 0 && length > static_cast<std::size_t>(most))
        throw SceneError(manifest.path, manifest.entries[i].line, "goldens[" + std::to_string(i) + "].name",
                         "too long: its file " + p.filename().string().substr(0, 24) + "... would have " +
                             std::to_string(length) + " bytes, more than the " + std::to_string(most) +
                             " the file system takes");
    }
}

// Refused before any render: an output that is the manifest, a scene, a golden image check
// reads or another output (update's images, check's evidence) under any spelling.
void check_outputs_writable(const GoldenOptions& o, const GoldenManifest& manifest, bool update) {
  check_name_lengths(o, manifest);
  std::vector<PathRole> inputs{{o.manifest, "the manifest"}}, outputs{{o.csv, "--csv"}, {o.summary, "--summary"},
                                                                  {o.junit, "--junit"}};
  for (const GoldenEntry& e : manifest.entries) {
    inputs.push_back({e.scene, "the scene of " + e.name});
    for (double t : e.times) {
      const std::string golden = golden_image_path(manifest, e, t);
      if (update) {
        outputs.push_back({golden, "the golden image"});
        continue;
      }
      inputs.push_back({golden, "the golden image"});
      outputs.push_back({evidence_path(o, golden, "actual"), "the evidence"});
      outputs.push_back({evidence_path(o, golden, "diff"), "the evidence"});
    }
  }
  refuse_clashing_paths(inputs, outputs);
  if (update)  // the golden images, after --csv, --summary and --junit: an unwritable folder is said before rendering
    for (std::size_t i = 3; i < outputs.size(); ++i) require_writable_parent(outputs[i].path, outputs[i].what);
  if (!o.csv.empty()) require_writable_parent(o.csv, "--csv");
  if (!o.junit.empty()) require_writable_parent(o.junit, "--junit");
  if (!o.summary.empty() && o.shard.empty()) require_writable_parent(o.summary, "--summary");
}

void commit_all(GoldenWork& work) {
  for (std::size_t i = 0; i < work.staged.size(); ++i) {
    try {
      work.staged[i]->commit();
    } catch (const OutputFileError& e) {
      throw RuntimeFailure(std::string(e.what()) + "; " + std::to_string(i) + " of " +
                           std::to_string(work.staged.size()) + " golden images written before it");
    }
    std::printf("wrote %s\n", work.staged[i]->path().c_str());
  }
}

int golden_shard(const GoldenOptions& o, const GoldenManifest& manifest, const std::vector<SceneDef>& scenes,
                 const std::vector<PictureLook>& looks) {
  StudyShard shard(o.shard, o.csv, "", o.summary, golden_plan(o, manifest, scenes));
  if (shard.todo().empty()) return shard.finish();
  const std::unique_ptr<Renderer> renderer = make_renderer(o.gl);
  for (std::size_t i : shard.todo()) {
    GoldenWork work;
    const Model model = build_model(scenes[i]);
    const LaneResult r = run_entry(o, manifest, i, scenes[i], looks[i], model, *renderer, false, work);
    std::string rows;
    for (const GoldenVerdict& v : work.verdicts) rows += golden_csv_row(v);
    shard.record(i, rows, entry_lane_json(manifest.entries[i], i, scenes[i], model, r, work.verdicts).dump());
  }
  return shard.finish();
}

}  // namespace clothsim::clip
