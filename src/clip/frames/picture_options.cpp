#include "picture_options.h"

#include <cmath>

#include "clip/common/cli_common.h"
#include "core/model/stiffness_estimate.h"
#include "scene/echo.h"
#include "scene/run_bounds.h"
#include "study/reference.h"
#include "view/camera_fit.h"
#include "view/snapshot.h"

namespace clothsim::clip {

constexpr double kMinColorValue = 1e-30, kMaxColorValue = 1e30, kMinColorSpan = 1e-4;

ColorRange parse_color_range(const std::string& text) {
  const std::vector<std::string> parts = split_list(text);
  if (parts.size() != 2) throw UsageError("--color-range: expected LO,HI, got " + in_quotes(text));
  ColorRange r;
  const std::optional<double> lo = parse_number_or_fraction(parts[0]), hi = parse_number_or_fraction(parts[1]);
  if (!lo || !hi) throw UsageError("--color-range: " + in_quotes(text) + " is not two numbers LO,HI");
  if (!(*lo > 0.0) || !(*hi > *lo))
    throw UsageError("--color-range: need 0 < LO < HI on a logarithmic scale, got " + in_quotes(text));
  // The scale is drawn in single precision: both ends within its range, HI distinguishable from LO.
  if (*lo < kMinColorValue || *hi > kMaxColorValue || *hi < *lo * (1.0 + kMinColorSpan))
    throw UsageError("--color-range: LO and HI must lie from 1e-30 to 1e30 with HI at least 1.0001 x LO, got " +
                     in_quotes(text));
  r.lo = *lo;
  r.hi = *hi;
  return r;
}

PictureLook resolve_picture_look(const PictureOptions& o, const SceneDef& scene, const std::vector<Lane>& lanes,
                                 bool compare) {
  PictureLook look;
  const std::string color = o.color ? *o.color : !scene.render.color.empty() ? scene.render.color : compare ? "error" : "checker";
  const std::optional<FieldKind> kind = parse_field_kind(color);
  if (!kind) throw UsageError("--color: unknown colouring " + in_quotes(color) + " (expected checker, error, strain or speed)");
  look.color = *kind;
  if (look.color == FieldKind::Error && !o.no_reference_cache) {  // (only the error's reference is cached)
    try {
      look.reference_cache = analysis::reference_cache_settings();
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  if (!o.color_range.empty()) {
    if (look.color == FieldKind::None) throw UsageError("--color-range goes with --color error, strain or speed");
    look.color_range = parse_color_range(o.color_range);
  }
  const bool inset_energy = o.inset == "energy";
  if (!o.reference.empty() && look.color != FieldKind::Error && !(compare && inset_energy))
    throw UsageError(compare ? "--reference goes with --color error or --inset energy (it is what the error and the "
                               "energy are measured against)"
                             : "--reference goes with --color error (it is what the error is measured against)");
  if (look.color == FieldKind::Error || (compare && inset_energy)) {
    look.reference = parse_reference(o.reference, lanes);
    look.reference_is_default = o.reference.empty();
    if (integrator_info(look.reference->kind).adaptive)
      look.reference_tolerance = look.reference->rtol > 0.0 ? look.reference->rtol : analysis::kReferenceTolerance;
  }

  look.camera_auto = scene.render.camera_auto;
  if (o.camera) {
    if (*o.camera == "auto") look.camera_auto = true;
    else if (*o.camera == "scene") look.camera_auto = false;
    else throw UsageError("--camera: expected auto or scene, got " + in_quotes(*o.camera));
  }
  const std::string overlay = o.overlay ? *o.overlay : scene.render.overlay;
  const std::optional<OverlayMode> mode = parse_overlay_mode(overlay);
  if (!mode) throw UsageError("--overlay: expected full, label or none, got " + in_quotes(overlay));
  look.overlay = *mode;
  // Same command, same bytes: measured time goes on a picture only when asked for.
  const std::string cost = o.overlay_cost.empty() ? "work" : o.overlay_cost;
  if (cost != "work" && cost != "evals" && cost != "cpu")
    throw UsageError("--overlay-cost: expected work or cpu, got " + in_quotes(cost));
  look.overlay_cpu = cost == "cpu";
  if (o.inset != "energy" && o.inset != "none")
    throw UsageError("--inset: expected energy or none, got " + in_quotes(o.inset));
  look.inset_energy = o.inset == "energy";

  // A sample count in the scene says msaa (or none, at 1) by itself.
  const RenderDef& r = scene.render;
  const std::string antialias = o.antialias              ? *o.antialias
                                : !r.antialias.empty()   ? r.antialias
                                : r.samples_given        ? (r.samples > 1 ? "msaa" : "none")
                                : compare                ? "fxaa"
                                                         : "msaa";
  if (antialias != "msaa" && antialias != "fxaa" && antialias != "none")
    throw UsageError("--antialias: expected msaa, fxaa or none, got " + in_quotes(antialias));
  look.samples = antialias == "msaa" ? (r.samples > 1 ? r.samples : kDefaultMsaaSamples) : 1;
  look.fxaa = antialias == "fxaa";
  return look;
}

void fit_reference_to_model(PictureLook& look, const Model& model, const SceneDef& scene,
                            const std::vector<Lane>& lanes) {
  if (look.reference && !look.reference_is_default && look.reference_tolerance > 0.0 && !analysis::smooth_scene(model))
    throw UsageError("--reference " + look.reference->stepless_spelling() +
                     ": the adaptive reference needs contacts without projection (collision.model: barrier); "
                     "give rk4@STEP on this scene");
  if (!look.reference || !look.reference_is_default) return;
  look.reference_tolerance = analysis::smooth_scene(model) ? analysis::kReferenceTolerance : 0.0;
  Lane& ref = *look.reference;
  const double limit = analysis::predicted_limit(analysis::estimate_stiffness(model), ref.kind, model.implicit);
  if (!(limit < ref.dt) || !(limit > 0.0)) return;
  // The smallest lane step divided into whole reference steps: the reference still lands
  // where those lanes land (frame_pipeline.cpp).
  const double lane_step = smallest_step(lanes);
  ref.dt = lane_step / std::ceil(lane_step / limit);
  ref.step_text = step_string(ref.dt);
  const std::string too_long = run_bounds_problem(scene.duration, ref.dt, scene.render.fps);
  if (!too_long.empty())
    throw UsageError("the reference for --color error (" + ref.spelling() +
                     ", within RK4's predicted stable step on this scene): " + too_long +
                     "; give --reference NAME@STEP or --color checker");
}

RenderCamera auto_camera(const Model& model, const RenderDef& scene_render, double aspect) {
  return fit_scene_camera(model, scene_render, aspect);  // view/snapshot.h: the Python module's too
}

void apply_look(const PictureLook& look, PipelineConfig& c) {
  c.color = look.color;
  c.color_range = look.color_range;
  c.reference = look.reference;
  c.reference_tolerance = look.reference_tolerance;
  c.reference_cache = look.reference_cache;
  c.overlay = look.overlay;
  c.overlay_cpu = look.overlay_cpu;
  c.inset_energy = look.inset_energy;
  c.samples = look.samples;
  c.fxaa = look.fxaa;
}

}  // namespace clothsim::clip
