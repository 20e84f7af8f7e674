// clothsim golden check|update MANIFEST.yaml: golden images of users' own scenes, the way
// pytest-regressions keeps data files. Each manifest entry (golden_manifest.h) is run like
// `run --still` at each of its times, rendered at its size, and then
//   check:  compared with its golden image by imgdiff's measure; on a mismatch the render and
//           an amplified diff are written beside the golden (NAME_tXms.actual.png, .diff.png)
//           or into --failures DIR. Exit 0 all match, 1 some differ or are missing.
//   update: the golden images are (re)written, all or none: each is rendered into a nameless
//           file, and they are named together once every one was made.
// check also writes a row per image (--csv) and a lane per entry (--summary), and runs a part
// of the manifest with --shard K/N|auto (entries split by estimated cost; `clothsim merge`
// joins the parts into the report, CSV and summary of one check: docs/cluster.md).
// SIGINT, SIGTERM and SIGHUP stop it with one line of what stays (docs/outputs.md).
// A bad manifest or scene, or an entry whose run would need more than --max-memory, exits 2
// before anything is rendered.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <memory>
#include <optional>

#include <unistd.h>

#include "clip/golden/golden_check.h"
#include "clip/golden/golden_manifest.h"
#include "clip/golden/golden_report.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/gl_options.h"
#include "clip/common/lanes.h"
#include "clip/common/memory_budget.h"
#include "clip/frames/run_budget.h"
#include "clip/frames/frame_pipeline.h"
#include "clip/frames/picture_options.h"
#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"
#include "render/image_diff.h"
#include "render/png_io.h"
#include "scene/build_model.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "study/work_precision.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::cli {
namespace {

int golden_command(const GoldenOptions& o, bool update) {
  install_interrupt_handler();  // the pipeline polls; a signal stops it with one line of what stays
  const GoldenManifest manifest = load_golden_manifest(o.manifest);
  std::vector<SceneDef> scenes;
  std::vector<PictureLook> looks;
  load_entries(o, manifest, scenes, looks);
  if (!o.failures_dir.empty() && !update) ensure_directory(o.failures_dir, "--failures");
  check_outputs_writable(o, manifest, update);
  if (!o.shard.empty() && !o.junit.empty())
    throw UsageError("--junit: a sharded check writes its parts for `clothsim merge`; check the whole manifest "
                     "for the XML (one process, no --shard)");
  if (!o.shard.empty()) return golden_shard(o, manifest, scenes, looks);
  const std::unique_ptr<Renderer> renderer = make_renderer(o.gl);

  int images = 0;
  GoldenWork work;
  std::vector<JsonObject> lanes;
  std::vector<std::string> not_written;  // written once every entry ran
  std::vector<double> seconds;  // each entry's run, wall clock (--junit's testcase time)
  for (const std::string& path : {o.csv, o.summary, o.junit})
    if (!path.empty()) not_written.push_back(path);
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const Model model = build_model(scenes[i]);
    images += static_cast<int>(manifest.entries[i].times.size());
    const auto start = std::chrono::steady_clock::now();
    const LaneResult r = run_entry(o, manifest, i, scenes[i], looks[i], model, *renderer, update, work, not_written);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    lanes.push_back(entry_lane_json(manifest.entries[i], i, scenes[i], model, r, work.verdicts));
  }
  if (update && work.bad > 0) {
    std::printf("golden: %d of %d images could not be made; nothing written (update writes all or none) (%s)\n",
                work.bad, images, o.manifest.c_str());
    return 1;
  }
  if (update) {
    commit_all(work);
    std::printf("golden: %d of %d images written (%s)\n", images, images, o.manifest.c_str());
    return kOk;
  }
  write_check_outputs(o, manifest, lanes, seconds, work);
  std::printf("%s\n", golden_tally(work.verdicts, o.manifest).c_str());
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
    if (!update) {
      sub->add_option("--failures", o->failures_dir, "Write actual and diff images of failures here instead")
          ->type_name("DIR");
      sub->add_option("--csv", o->csv, "Write one row per image: entry,image,t,result,rms,max,...")->type_name("FILE.csv");
      sub->add_option("--summary", o->summary, "Write each entry's run and images as JSON (docs/summary.md)")
          ->type_name("FILE.json");
      sub->add_option("--junit", o->junit,
                      "Write JUnit XML for CI: a test case per entry, its failing images' differences, each "
                      "diff image as an attachment (docs/golden.md)")
          ->type_name("FILE.xml");
      add_shard_option(sub, o->shard);
    }
    add_gl_options(sub, o->gl);
    add_max_memory_option(sub, o->max_memory);
    add_progress_options(sub);
    sub->callback([o, update, &command] { command = [o, update] { return golden_command(*o, update); }; });
  }
}

}  // namespace clothsim::cli
