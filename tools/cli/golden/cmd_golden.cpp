// clothsim golden check|update MANIFEST.yaml: golden images of users' own scenes, the way
// pytest-regressions keeps data files. Each manifest entry (golden_manifest.h) is run like
// `run --still` at each of its times, rendered at its size, and then
//   check:  compared with its golden image by imgdiff's measure; on a mismatch the render and
//           an amplified diff are written beside the golden (NAME_tXms.actual.png, .diff.png)
//           or into --failures DIR. Exit 0 all match, 1 some differ or are missing.
//   update: the golden images are (re)written, all or none: each is rendered into a nameless
//           file, and they are named together once every one was made.
// SIGINT, SIGTERM and SIGHUP stop it with one line of what stays (docs/outputs.md).
// A bad manifest or scene, or an entry whose run would need more than --max-memory, exits 2
// before anything is rendered.
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "golden_manifest.h"
#include "cli/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/gl_options.h"
#include "cli/common/lanes.h"
#include "cli/common/memory_budget.h"
#include "cli/common/run_budget.h"
#include "cli/frames/frame_pipeline.h"
#include "cli/frames/picture_options.h"
#include "render/image_diff.h"
#include "render/png_io.h"
#include "scene/build_model.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"

namespace clothsim::cli {
namespace {

namespace fs = std::filesystem;

struct GoldenOptions {
  std::string manifest;
  std::string failures_dir;  // empty: beside each golden image
  GlOptions gl;
  std::optional<double> max_memory;  // --max-memory SIZE in bytes (default: memory_budget.h)
};

// Where a failed check leaves its evidence: "drape_t1500ms.png" -> "drape_t1500ms.actual.png".
std::string evidence_path(const GoldenOptions& o, const std::string& golden, const char* kind) {
  const fs::path g(golden);
  const fs::path dir = o.failures_dir.empty() ? g.parent_path() : fs::path(o.failures_dir);
  return (dir / (g.stem().string() + "." + kind + ".png")).string();
}

// What the entries' runs leave: `update` holds every golden image nameless until all are
// rendered (all or nothing), `check` the evidence of the failures found so far.
struct GoldenWork {
  std::vector<std::unique_ptr<OutputFile>> staged;  // update: named together by commit_all()
  std::vector<std::string> evidence;                 // check: .actual.png and .diff.png written
  int bad = 0;                                       // images that differ, are missing or diverged
};

// Compares one render with its golden image; prints one line; returns whether it matched.
bool check_one(const GoldenOptions& o, const std::string& golden, const Image& actual, const DiffTolerance& tol,
               std::vector<std::string>& evidence) {
  const std::string name = fs::path(golden).filename().string();
  const std::string actual_path = evidence_path(o, golden, "actual"), diff_path = evidence_path(o, golden, "diff");
  std::string problem;
  bool with_diff = false;
  if (!fs::exists(golden)) {
    problem = "missing (`clothsim golden update` writes it)";
  } else {
    // The size from the header first: a golden of another size is never decoded (a huge one
    // would otherwise take memory the budget did not count).
    const PngSize size = read_png_size(golden);
    if (size.width != actual.width || size.height != actual.height) {
      problem = "golden is " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                ", the render " + std::to_string(actual.width) + "x" + std::to_string(actual.height);
    } else {
      const Image expected = read_png(golden);
      const DiffStats stats = compare_images(expected, actual, tol.pixel_threshold);
      if (within_tolerance(stats, tol)) {
        std::printf("ok    %s  rms %.3f, max %d, %.3f%% past %d\n", name.c_str(), stats.rms, stats.max,
                    100.0 * stats.over_fraction, tol.pixel_threshold);
        fs::remove(actual_path);  // evidence of an earlier failure no longer holds
        fs::remove(diff_path);
        return true;
      }
      char text[160];
      std::snprintf(text, sizeof text, "rms %.3f (tolerance %g), max %d, %.3f%% past %d (tolerance %g%%)",
                    stats.rms, tol.max_rms, stats.max, 100.0 * stats.over_fraction, tol.pixel_threshold,
                    100.0 * tol.max_over_fraction);
      problem = text;
      write_png(diff_path, diff_image(expected, actual));
      evidence.push_back(diff_path);
      with_diff = true;
    }
  }
  write_png(actual_path, actual);
  evidence.push_back(actual_path);
  std::printf("FAIL  %s  %s; actual: %s%s\n", name.c_str(), problem.c_str(), actual_path.c_str(),
              with_diff ? (", diff: " + diff_path).c_str() : "");
  return false;
}

// Checks (or writes) the picture at each of an entry's times as the pipeline reaches it.
class GoldenOutput final : public FrameOutput {
 public:
  GoldenOutput(const GoldenOptions& o, const GoldenManifest& manifest, const GoldenEntry& entry, bool update,
               const Model& model, const Renderer& renderer, GoldenWork& work)
      : o_(o), manifest_(manifest), entry_(entry), update_(update), model_(model), renderer_(renderer), work_(work) {}
  std::string what() const override { return "golden"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.column < 0) return;
    const double t = entry_.times[static_cast<std::size_t>(target.column)];
    const std::string golden = golden_image_path(manifest_, entry_, t);
    const LaneFrame& f = *lanes.front().frame;
    if (f.divergence) {  // this image and the later ones of the entry cannot be made
      std::printf("FAIL  %s  %s diverged at t = %.6g s: %s\n", fs::path(golden).filename().c_str(),
                  entry_.scene.c_str(), f.divergence->t, f.divergence->reason.c_str());
      ++work_.bad;
      return;
    }
    if (update_) {
      // Into a nameless file held until every image is made (written through /proc/self/fd).
      work_.staged.push_back(std::make_unique<OutputFile>(golden));
      write_png(work_.staged.back()->reopen_path(), *lanes.front().image,
                with_renderer({{"scene", model_.name}, {"integrator", std::string(integrator_name(lanes.front().spec->kind))},
                               {"t", std::to_string(t)}, {"software", "clothsim " CLOTHSIM_VERSION}},
                              renderer_));
    } else if (!check_one(o_, golden, *lanes.front().image, entry_.tolerance, work_.evidence)) {
      ++work_.bad;
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
  const GoldenOptions& o_;
  const GoldenManifest& manifest_;
  const GoldenEntry& entry_;
  bool update_;
  const Model& model_;
  const Renderer& renderer_;
  GoldenWork& work_;
};

// update's end: every image made, so all are named now, one rename each.
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
      if (!too_long.empty()) throw SceneError(manifest.path, e.line, key + ".dt", too_long);
    }
    for (double t : e.times)
      if (t > scenes.back().duration + 1e-9) {
        char what[160];
        std::snprintf(what, sizeof what, "%g s is past the scene's duration (%g s): the run has no picture there", t,
                      scenes.back().duration);
        throw SceneError(manifest.path, e.line, key + ".times", what);
      }
    // The pictures `run --still` makes (the frame pipeline with one lane: the scene's camera,
    // colouring and overlay), and the peak memory of that run at the entry's size: entries run
    // one after another, so each is held to --max-memory on its own.
    const SceneDef& scene = scenes.back();
    const LaneSpec lane{scene.integrator, scene.dt, step_string(scene.dt), false};
    looks.push_back(resolve_picture_look({}, scene, {lane}, /*compare=*/false));
    run_budget(scene, looks.back(), {/*rendering=*/true, e.width, e.height, /*video=*/false})
        .check(manifest.path + (e.line > 0 ? ":" + std::to_string(e.line) : "") + ": " + key + " (" + e.scene + ")",
               o.max_memory);
  }
}

int golden_command(const GoldenOptions& o, bool update) {
  install_interrupt_handler();  // the pipeline polls; a signal stops it with one line of what stays
  const GoldenManifest manifest = load_golden_manifest(o.manifest);
  std::vector<SceneDef> scenes;
  std::vector<PictureLook> looks;
  load_entries(o, manifest, scenes, looks);
  if (!o.failures_dir.empty() && !update) ensure_directory(o.failures_dir, "--failures");
  const std::unique_ptr<Renderer> renderer = make_renderer(o.gl);

  int images = 0;
  GoldenWork work;
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const GoldenEntry& e = manifest.entries[i];
    const SceneDef& scene = scenes[i];
    const Model model = build_model(scene);
    images += static_cast<int>(e.times.size());
    // One picture per time, taken as a contact sheet's columns.
    const LaneSpec lane{scene.integrator, scene.dt, step_string(scene.dt), false};
    PictureLook look = looks[i];
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
    FramePipeline pipeline(model, targets, {lane}, config, renderer.get());
    pipeline.add(std::make_unique<GoldenOutput>(o, manifest, e, update, model, *renderer, work));
    pipeline.run("golden " + model.name);
  }
  if (update && work.bad > 0) {
    std::printf("golden: %d of %d images could not be made; nothing written (update writes all or none) (%s)\n",
                work.bad, images, o.manifest.c_str());
    return 1;
  }
  if (update) {
    commit_all(work);
    std::printf("golden: %d of %d images written (%s)\n", images, images, o.manifest.c_str());
  } else {
    std::printf("golden: %d of %d images match (%s)\n", images - work.bad, images, o.manifest.c_str());
  }
  return work.bad == 0 ? kOk : 1;
}

}  // namespace

void add_golden_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<GoldenOptions>();
  CLI::App* golden = app.add_subcommand(
      "golden", "Golden images of your own scenes from a manifest: check them, or update them");
  golden->require_subcommand(1);
  golden->footer(
      "Manifest format: docs/golden.md. Exit codes: 0 every image matches (or was written), 1 some\n"
      "differ, are missing or diverged, 2 a bad manifest or scene (one line: file, line, key).");
  for (const bool update : {false, true}) {
    CLI::App* sub = golden->add_subcommand(
        update ? "update" : "check",
        update ? "Render every entry and (re)write its golden images beside the manifest"
               : "Render every entry and compare it with its golden image; on a mismatch write the render "
                 "(NAME.actual.png) and an amplified diff (NAME.diff.png) beside the golden");
    sub->add_option("MANIFEST", o->manifest, "The manifest (YAML)")->required()->type_name("MANIFEST.yaml");
    if (!update)
      sub->add_option("--failures", o->failures_dir, "Write actual and diff images of failures here instead")
          ->type_name("DIR");
    add_gl_options(sub, o->gl);
    add_max_memory_option(sub, o->max_memory);
    add_progress_options(sub);
    sub->callback([o, update, &command] { command = [o, update] { return golden_command(*o, update); }; });
  }
}

}  // namespace clothsim::cli
