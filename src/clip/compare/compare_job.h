// What `clothsim compare` does, as a library under the CLI (tools/cli/compare/cmd_compare.cpp,
// which parses the options and prints the results) and any other front end:
//
//     CompareRequest -> plan_compare (everything checked, the model built, the steps chosen)
//         -> ComparePlan, one CompareLane per lane -> the frame pipeline with its outputs
//
// The plan is a value, made once and movable, and nothing runs while it is made but the --match
// pilots, which finish inside it: run_compare starts the lanes and the reference (or serves the
// reference from the cache, study/reference_cache.h). The model, the targets and the --vary
// models sit behind pointers it owns, so the lanes read those wherever the plan moves.
// Every function throws UsageError (exit 2) or RuntimeFailure (exit 1) with the one-line
// message the CLI prints.
#pragma once

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clip/common/gl_options.h"
#include "clip/common/lanes.h"
#include "clip/common/scene_options.h"
#include "clip/common/summary_json.h"
#include "clip/common/plan_parts.h"
#include "clip/compare/compare_summary.h"
#include "clip/frames/frame_pipeline.h"
#include "clip/frames/frame_sink.h"
#include "clip/frames/pipeline_outputs.h"
#include "clip/frames/picture_options.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "render/renderer.h"
#include "scene/scene_def.h"
#include "render/video/tiling.h"

namespace clothsim::clip {

// What is asked: compare's options, one field each (docs/cli.md, compare).
struct CompareRequest {
  SceneOptions scene;
  std::string integrators = default_comparison_list();  // the course's four, by name
  std::string layout = "auto";
  std::string video, frames_dir, dt, sheet, times, still_out, export_path;
  std::optional<double> still_t;
  std::vector<std::string> match{"cost"};  // --match cost | error TOL | none
  std::string vary;                         // --vary KEY=V1,V2,...
  bool integrators_given = false;           // --integrators given (a --vary grid's rows)
  bool match_given = false;                 // --match given (--vary matches only when asked)
  int crf = VideoOptions{}.crf;
  std::string preset = VideoOptions{}.preset;
  GlOptions gl;
  PictureOptions look;
  std::string summary;  // --summary FILE.json
  std::string shard;    // --shard K/N|auto, with --frames only (compare_shard.h)
  // A front end that takes the lanes' table itself (Python's compare()): a compare that writes
  // no file is then not refused as work for nothing.
  bool table_wanted = false;
  // A front end that takes a row per lane per clip frame (Python's compare, run_compare's
  // `rows`): the clip's frames are targets, as with --video, even when no clip is written,
  // and so is the end, where it falls between frames.
  bool frame_rows_wanted = false;
};

// One lane of a comparison: what it runs, what it is called and where it writes.
struct CompareLane {
  Lane spec;
  std::string dir;               // its folder under --frames, and its part of --export's names
  const Model* model = nullptr;  // --vary: its value's model; nullptr: the plan's
  std::string label;             // --vary: its tile's and sheet row's label ("rk4  ks = 2e4"); "" its own
  std::string value;             // --vary: its value alone ("ks = 2e4"); "" without --vary
  std::string name;              // its row in the table and the summary ("rk4", "rk4, ks = 2e4")
  std::string step_choice;       // how its step was chosen (--match)
};

// Everything compare does, worked out and checked before any lane runs.
struct ComparePlan {
  SceneDef scene;
  std::vector<CompareLane> lanes;
  GridLayout layout;
  PictureLook look;
  bool with_frames = false, rendering = false;
  std::vector<double> sheet_times;
  std::optional<TileGrid> grid;
  int legend_width = 0;  // the colour bar's strip right of the grid (grid_legend.h)
  std::shared_ptr<const TargetPlan> targets;  // behind pointers: a moved plan's lanes still read them
  std::shared_ptr<const Model> model;
  // --vary: per value, its scene and model (a deque: the lanes and the pipeline keep pointers).
  std::vector<SceneDef> vary_scenes;
  std::deque<Model> vary_models;
  std::optional<Lane> error_reference;  // --match error: the reference the steps were matched against
  // --vary with --color error: per value, the reference its lanes are measured against
  // (PipelineConfig::variant_references), each fitted to its value's model.
  std::vector<VariantReference> variant_references;

  // The lanes' fields one by one, for the functions that take a list.
  std::vector<Lane> specs() const;
  std::vector<std::string> dirs() const;
  std::vector<const Model*> models() const;   // empty without --vary (every lane: the plan's model)
  std::vector<std::string> labels() const;    // empty without --vary (the lanes' own labels)
  SummaryContext summary_context() const;
};

// 1. Everything that can be wrong, before any simulation; the steps chosen. No thread outlives it.
ComparePlan plan_compare(const CompareRequest& o);
// --shard: the plan of the whole comparison, narrowed to this part's lanes (compare_shard.h).
void keep_shard_lanes(const CompareRequest& o, ComparePlan& p);
// What a front end plans: with --shard, the part's outputs checked (--frames only), then
// plan_compare and the part's lanes kept. Nothing when the part has no lane (more parts than
// lanes): nothing to run.
std::optional<ComparePlan> plan_compare_part(const CompareRequest& o);
// The renderer for the tiles (none when nothing is drawn); a GL failure or tiles past its limit now.
std::unique_ptr<Renderer> make_checked_renderer(const CompareRequest& o, const ComparePlan& p);
PipelineConfig pipeline_config(const ComparePlan& p);
// 2. The outputs the pipeline feeds (each removes its temporary if destroyed before finish()).
void add_outputs(const CompareRequest& o, const ComparePlan& p, FramePipeline& pipeline, Renderer* renderer);
// 3. Runs the plan's lanes through the pipeline into every output asked for but the summary
// (written after it: write_compare_summary), and into `rows` when given (a row per lane per
// clip frame: make_frame_rows_output; plan with CompareRequest::frame_rows_wanted). On a signal
// (interrupted()) stops, drops what is incomplete and throws RuntimeFailure saying what stays.
PipelineReport run_compare(const CompareRequest& o, const ComparePlan& p, std::vector<LaneFrameRow>* rows = nullptr);

// The lanes and the reference as --summary's objects (docs/summary.md), and the file with
// compare's keys (color, match, the scale, the reference) beside them.
std::vector<JsonObject> compare_lanes_json(const ComparePlan& p, const PipelineReport& report);
void write_compare_summary(const CompareRequest& o, const ComparePlan& p, const PipelineReport& report);

}  // namespace clothsim::clip
