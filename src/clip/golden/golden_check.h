// What `clothsim golden check|update` does with a manifest (golden_manifest.h): reads every
// entry's scene and bounds its run before any render, runs each entry as `run --still` makes
// its pictures, compares each with its golden image (or stages it for update), and plans a
// shard of the check. tools/cli/golden/cmd_golden.cpp parses, prints the tally, and exits.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clip/common/gl_options.h"
#include "clip/common/summary_json.h"
#include "clip/frames/frame_pipeline.h"
#include "clip/frames/picture_options.h"
#include "clip/golden/golden_manifest.h"
#include "clip/golden/golden_report.h"
#include "clip/studies/study_shard.h"
#include "render/image_diff.h"
#include "io/output_file.h"
#include "scene/scene_def.h"

namespace clothsim::clip {

struct GoldenOptions {
  std::string manifest;
  std::string failures_dir;  // empty: beside each golden image
  std::string csv, summary, junit, shard;  // check only
  GlOptions gl;
  std::optional<double> max_memory;  // --max-memory SIZE in bytes (default: memory_budget.h)
};

// Where a failed check leaves its evidence: "drape_t1500ms.png" -> "drape_t1500ms.actual.png".
std::string evidence_path(const GoldenOptions& o, const std::string& golden, const char* kind);

// What the entries' runs leave: `update` holds every golden image nameless until all are
// rendered (all or nothing), `check` the evidence of the failures found so far.
struct GoldenWork {
  std::vector<std::unique_ptr<OutputFile>> staged;  // update: named together by commit_all()
  std::vector<std::string> evidence;                 // check: .actual.png and .diff.png written
  std::vector<GoldenVerdict> verdicts;               // check: one per image, in manifest order
  int bad = 0;                                       // images that differ, are missing or diverged
};

// Compares one render with its golden image, writing the evidence of a mismatch.
GoldenVerdict check_one(const GoldenOptions& o, const std::string& golden, const Image& actual, const DiffTolerance& tol,
                        std::vector<std::string>& evidence);

// Every scene is read, and its run's memory estimated, before any rendering, so a bad one
// fails at once (exit 2).
void load_entries(const GoldenOptions& o, const GoldenManifest& manifest, std::vector<SceneDef>& scenes,
                  std::vector<PictureLook>& looks);

// An entry's run, as run --still makes its pictures: each time a contact sheet's column,
// checked (or staged) as the pipeline reaches it. Returns the run's lane (totals, divergence).
LaneResult run_entry(const GoldenOptions& o, const GoldenManifest& manifest, std::size_t i, const SceneDef& scene,
                     const PictureLook& entry_look, const Model& model, Renderer& renderer, bool update,
                     GoldenWork& work, const std::vector<std::string>& not_written = {});

// An entry in the summary: its run as a lane (the common keys), its name and its images.
JsonObject entry_lane_json(const GoldenEntry& e, std::size_t i, const SceneDef& scene, const Model& model,
                           const LaneResult& r, const std::vector<GoldenVerdict>& verdicts);

inline constexpr double kPixelCost = 1.0;  // a pixel's weight in entry_cost

// An entry's estimated cost in particle-force-evaluations: its run to the latest time and
// its pictures, a pixel counted as kPixelCost of them (docs/cluster.md).
double entry_cost(const GoldenEntry& e, const SceneDef& scene);

// What a part of the check is a part of: every entry's scene bytes and settings.
ShardPlan golden_plan(const GoldenOptions& o, const GoldenManifest& manifest, const std::vector<SceneDef>& scenes);

// check's --csv, --summary and --junit (`seconds`: each entry's run), once every entry ran.
void write_check_outputs(const GoldenOptions& o, const GoldenManifest& manifest, const std::vector<JsonObject>& lanes,
                         const std::vector<double>& seconds, const GoldenWork& work);

// A name whose image (or its evidence, NAME_tT.actual.png) is longer than the file system
// takes fails at the first write: refused at its key before any render.
void check_name_lengths(const GoldenOptions& o, const GoldenManifest& manifest);

// Refused before any render: an output that is the manifest, a scene, a golden image check
// reads or another output (update's images, check's evidence) under any spelling.
void check_outputs_writable(const GoldenOptions& o, const GoldenManifest& manifest, bool update);

// update's end: every image made, so all are named now, one rename each ("wrote PATH" on
// stdout); RuntimeFailure at the first that cannot be, saying how many were written before it.
void commit_all(GoldenWork& work);

// check --shard: this process's entries, each journaled with its rows and lane as it finishes. A
// part whose images differ still returns 0 (the array's merge job must run): merge fails.
int golden_shard(const GoldenOptions& o, const GoldenManifest& manifest, const std::vector<SceneDef>& scenes,
                 const std::vector<PictureLook>& looks);

}  // namespace clothsim::clip
