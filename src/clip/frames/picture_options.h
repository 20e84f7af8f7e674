// How the pictures of `run` and `compare` look, from the scene's render keys and the options
// that override them: colouring (--color, --color-range, --reference), camera (--camera),
// overlay text (--overlay, --overlay-cost), the energy inset (--inset) and antialiasing
// (--antialias).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "frame_pipeline.h"
#include "clip/common/lanes.h"
#include "core/model/model.h"
#include "scene/scene_def.h"
#include "study/reference_cache.h"

namespace clothsim::clip {

struct PictureOptions {
  std::optional<std::string> color;      // --color checker|error|strain|speed
  std::string color_range;               // --color-range LO,HI
  std::string reference;                 // --reference NAME[@STEP]
  bool no_reference_cache = false;       // --no-reference-cache
  std::optional<std::string> camera;     // --camera auto|scene
  std::optional<std::string> overlay;    // --overlay full|label|none
  std::string overlay_cost;              // --overlay-cost work|cpu (evals: work); "": cpu in compare, work in run
  std::string inset = "none";            // --inset energy|none
  std::optional<std::string> antialias;  // --antialias msaa|fxaa|none
};

// The options resolved against the scene, every bad value a UsageError naming the option.
struct PictureLook {
  FieldKind color = FieldKind::None;
  std::optional<ColorRange> color_range;
  std::optional<Lane> reference;  // with color error, and in compare with inset energy
  bool reference_is_default = false;  // not from --reference: fit_reference_to_model() may shorten its step
  // > 0: the default reference of a smooth scene, the adaptive solve at this tolerance
  // (study/reference.h; fit_reference_to_model() sets it)
  double reference_tolerance = 0.0;
  // The reference's cache (study/reference_cache.h): from the environment, dir "" with
  // --no-reference-cache.
  analysis::ReferenceCacheSettings reference_cache;
  bool camera_auto = false;
  OverlayMode overlay = OverlayMode::Full;
  bool overlay_cpu = false;
  bool inset_energy = false;
  int samples = kDefaultMsaaSamples;  // MSAA samples (1: none)
  bool fxaa = false;  // edges smoothed on the CPU (render/fxaa.h)
};
PictureLook resolve_picture_look(const PictureOptions& options, const SceneDef& scene, const std::vector<Lane>& lanes,
                                 bool compare);

// The default reference (RK4 at a quarter of the smallest lane step) where that step is above
// RK4's predicted stability limit on this model (analysis/stiffness_estimate.h: a lower
// estimate of the true limit): the smallest lane step divided into as few whole steps as keep
// within the limit instead, so the error colouring does not lose its reference to a blow-up
// (RK4 at 1/120 s on stiff.yaml) and still lands where those lanes land. The reference's steps are then bounded as every run's (a UsageError naming
// --reference past the bound). A --reference the user gave is left as given.
void fit_reference_to_model(PictureLook& look, const Model& model, const SceneDef& scene,
                            const std::vector<Lane>& lanes);

// --color-range "1e-6,1e-2": two finite numbers, 0 < LO < HI.
ColorRange parse_color_range(const std::string& text);

// render.camera: auto: a camera framing the cloth at rest and the spheres (camera_fit.h) for
// pictures of `aspect` (width / height), fixed for the whole clip.
RenderCamera auto_camera(const Model& model, const RenderDef& scene_render, double aspect);

// The pipeline's settings for the look.
void apply_look(const PictureLook& look, PipelineConfig& config);

}  // namespace clothsim::clip
