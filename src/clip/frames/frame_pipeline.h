// The one frame pipeline of `run` and `compare`:
//
//     output times (TargetPlan) -> lanes (one simulation each, LaneWorker threads)
//         -> colouring, overlay, rendering (this thread) -> outputs that watch every target
//
// An output (PNG sequence, video, still, contact sheet, metrics) sees every target in time
// order with every lane's frame and picture; `run` is a pipeline of one lane, `compare` one of
// several, and neither has a frame loop of its own.
//
// A lane that diverges hands over the picture of its last finite state, marked DIVERGED with
// the time, step and reason; the pipeline holds it for the rest of the clip (a `run` stops
// there instead: stop_when_all_frozen). A tile (compare) holds its last sane frame instead,
// the last target whose state passed the divergence checks, at the usual camera and colouring,
// captioned with the divergence and the step predicted stable: it stays beside lanes that ran
// on, and the blown-up state's close-up says nothing there. Colouring by error runs a reference lane alongside,
// never shown. A field's colour scale is fixed for the whole clip: given, or chosen from the
// data of the first second (those targets are held back until it is known, then printed).
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lane_worker.h"
#include "render/image.h"
#include "render/renderer.h"

namespace clothsim::clip {

enum class OverlayMode { Full, Label, None };
std::optional<OverlayMode> parse_overlay_mode(std::string_view text);  // full|label|none

// A colour scale not given is chosen from the data of the clip's first second (or the whole
// run when shorter): TargetPlan::with_scale_window(kColorScaleWindow) makes those instants
// targets whatever the outputs.
inline constexpr double kColorScaleWindow = 1.0;  // s

struct ColorRange {
  double lo = 0.0, hi = 0.0;  // field units, 0 < lo < hi (a logarithmic scale)
};

// One reference of compare --vary --color error (PipelineConfig::variant_references).
struct VariantReference {
  const Model* model = nullptr;  // one of PipelineConfig::lane_models: the lanes it measures
  Lane spec;
  double tolerance = 0.0;        // > 0: the adaptive solve at this tolerance (as reference_tolerance)
  std::string label;             // the value, as the lanes' names give it ("collision.model = barrier")
};

struct PipelineConfig {
  bool rendering = false;          // pictures are made (some output shows them)
  int width = 0, height = 0;       // of each lane's picture (a tile)
  bool tiles = false;              // pictures are tiles of a grid that labels them and draws their
                                   // one colour bar beside them (compare: grid_legend.h)
  OverlayMode overlay = OverlayMode::Full;
  bool overlay_cpu = false;        // --overlay-cost cpu: measured CPU time beside the work units
  bool judge = false;              // compare: judge each lane's plausibility (plausibility.h), WRONG on its tile
  FieldKind color = FieldKind::None;
  std::optional<ColorRange> color_range;  // --color-range; else from the first second
  bool inset_energy = false;       // --inset energy
  // compare --inset energy: a lane run alongside (the reference), never shown, whose total
  // energy the inset subtracts (frame_decoration.h); none: the inset shows E - E(0).
  std::optional<Lane> energy_reference;
  int samples = kDefaultMsaaSamples;  // MSAA samples of each picture (1: none)
  bool fxaa = false;               // edges smoothed on the CPU instead (render/fxaa.h)
  bool metrics = false;            // an output reads LaneFrame::metrics
  bool final_state = false;        // keep the lanes' final states (run --state)
  bool stop_when_all_frozen = false;  // run: a diverged lane ends the pipeline
  std::optional<Lane> reference;  // for FieldKind::Error
  // > 0: that reference is the adaptive solve at this tolerance (LaneNeeds::adaptive_tolerance).
  double reference_tolerance = 0.0;
  // Where the error's references are served from when computed before, and stored once
  // computed (study/reference_cache.h; dir "": always computed, never stored).
  analysis::ReferenceCacheSettings reference_cache;
  RenderDef scene_render;          // the scene's render block: camera, springs, particles
  std::optional<RenderCamera> camera;  // replaces the model's (render.camera: auto, fitted)
  std::string command = "compare";     // for messages: "compare: colour scale ..."
  // Per lane, the model it runs when it is not the pipeline's (compare --vary: each value its
  // own scene); empty: the pipeline's model for every lane. A lane's own settings (`:N`, the
  // fixed point) are no other model: its run carries them (clip::lane_settings).
  std::vector<const Model*> lane_models;
  // compare --vary --color error: a reference per value, in place of `reference`. Each runs on
  // its value's model and measures only the lanes of that model: a value is its own scene, so
  // its lanes are measured against its own reference, never another value's.
  std::vector<VariantReference> variant_references;
};

// One lane at one target, as outputs see it.
struct LaneView {
  const Lane* spec = nullptr;
  const LaneFrame* frame = nullptr;  // the lane's latest (a frozen lane's held frame)
  const Image* image = nullptr;      // its picture, when rendering
  bool fresh = false;                // handed over at this target (not a held frame)
  const ColorScale* legend = nullptr;  // the pictures' colour scale (one for every lane), when coloured
  const std::vector<float>* field = nullptr;  // for an output that needs_bodies(): its colouring field (may be empty)
  // The colouring field's largest value over the particles at this target, as LaneReport's
  // field_last takes it (with --color error: the distance from the reference, m); NaN when
  // the lane has none here (not fresh, not coloured, or the reference did not serve it).
  double field_largest = std::numeric_limits<double>::quiet_NaN();
  // The step the scene's stiffness estimate predicts stable for the lane's method (s;
  // analysis::predicted_limit, infinity: none): what a diverged lane's caption says.
  double predicted_limit = std::numeric_limits<double>::infinity();
};

class FrameOutput {
 public:
  virtual ~FrameOutput() = default;
  virtual std::string what() const = 0;  // "video", "frames", ... for the time breakdown
  // Every target in time order, with every lane (in lane order).
  virtual void on_target(const Target& target, const std::vector<LaneView>& lanes) = 0;
  // Completes the output (named only now); called once after the last target.
  virtual void finish() = 0;
  // A signal, or another output failing: drops what is incomplete and says what stays on disk
  // and what is not written.
  virtual void abandon(std::vector<std::string>& kept, std::vector<std::string>& lost) = 0;
  // After finish(), when a later output failed: what this one wrote, which stays.
  virtual void kept(std::vector<std::string>& kept) { (void)kept; }
  // Whether it reads LaneFrame::bodies (every body's x and v: --export) and LaneView::field.
  virtual bool needs_bodies() const { return false; }
};

// One lane's run as the pipeline saw it.
struct LaneReport {
  LaneResult result;
  // The colouring field's largest value over every target and over the particles, and its
  // largest value at the last target where the lane had one (NaN when never coloured): with
  // --color error, how far the lane strayed from the reference, in numbers.
  double field_max = std::numeric_limits<double>::quiet_NaN();
  double field_last = std::numeric_limits<double>::quiet_NaN();
  double field_last_t = std::numeric_limits<double>::quiet_NaN();  // s: the frame field_last is from
  // What field_max covers: how many targets had the field, the first one's time. A sheet or a
  // still samples the targets it shows (and the colour scale's first second), a clip every frame.
  long field_count = 0;
  double field_first_t = std::numeric_limits<double>::quiet_NaN();
  // How many distinct states of the lane (distinct steps) those targets showed: fewer than
  // field_count where the lane's step is longer than the frame interval and it stands on one
  // state for several targets (rk4@0.1 at 30 frames/s: 3 states in the first 0.2 s's 7 frames).
  long field_states = 0;
  // The verdict of plausibility.h ("" for a plausible lane), and the largest rise of the total
  // energy above E(0), J (with PipelineConfig::judge).
  std::string wrong;
  double energy_rise = 0.0;
  int reference = -1;  // the index in PipelineReport::references of its reference (-1: none)
};


// A reference lane's run (the error colouring's), and which value it stands for under --vary.
struct ReferenceReport {
  LaneResult result;
  std::string label;  // VariantReference::label; "" for the one reference of a comparison
};

struct PipelineReport {
  std::vector<LaneReport> lanes;
  // The error colouring's references: none, the one every lane is measured against, or one per
  // --vary value (LaneReport::reference says whose a lane is).
  std::vector<ReferenceReport> references;
  std::optional<ColorRange> color_range;  // the scale used
  double wait_seconds = 0.0, render_seconds = 0.0;  // this thread: waiting on lanes, rendering
  std::vector<std::pair<std::string, double>> output_seconds;  // per output
  long targets = 0;  // processed
};

// The reference lane `lane` is measured against; null when none.
const LaneResult* lane_reference(const PipelineReport& report, std::size_t lane);

// A lane's error is unresolved when its largest is under this times the reference's estimated
// error: compare's table and summary judge the clip so (compare_summary.h), and a tile each
// frame by the largest error and the reference's estimate so far, marked UNRESOLVED.
inline constexpr double kUnresolvedFactor = 10.0;

class FramePipeline {
 public:
  // `model` and `plan` must outlive the pipeline; `renderer` is needed when rendering.
  FramePipeline(const Model& model, const TargetPlan& plan, std::vector<Lane> lanes,
                PipelineConfig config, Renderer* renderer);
  ~FramePipeline();
  void add(std::unique_ptr<FrameOutput> output);

  // Runs every lane through every target, feeding the outputs, then finishes them. On a signal
  // stops every lane, abandons the outputs and throws RuntimeFailure with the one-line message
  // of what stays (interruption_message). `not_written` lists outputs the caller writes after
  // the pipeline (a summary, a state), so the message names them too.
  PipelineReport run(const std::string& progress_label, const std::vector<std::string>& not_written = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The overlay lines of a lane's picture: `single` (run: scene, lane, time, cost) or a tile's
// (time and cost; the grid labels the tile with the lane). The cost in spring-pass
// equivalents always (core/work_units.h: an implicit lane's Newton work counted, not only its
// force evaluations), measured CPU time beside it only with `cpu` (overlay_text.h, cost_line).
std::vector<std::string> lane_overlay(const Model& model, const Lane& lane, const LaneFrame& frame,
                                      OverlayMode mode, bool single, bool cpu);

// The colour scale from the first second's data: the largest finite value rounded up to a
// power of ten, and `decades` below it (error 4, strain and speed 3). nullopt with no positive
// value (the scene at rest, or the lanes or the reference diverged before one was measured: the
// pipeline's message says which).
std::optional<ColorRange> range_from_data(const std::vector<const std::vector<float>*>& fields, FieldKind kind);

}  // namespace clothsim::clip
