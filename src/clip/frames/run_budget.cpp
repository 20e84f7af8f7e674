#include "run_budget.h"

#include <algorithm>
#include <string>

#include "clip/frames/lane_worker.h"  // reference_queue_capacity
#include "clip/reference/reference_stand.h"  // reference_positions_bytes
#include "scene/memory_estimate.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

MemoryBudget run_budget(const SceneDef& scene, const PictureLook& look, const RunPictures& pictures) {
  const int w = pictures.width, h = pictures.height;
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  // The run steps on a lane thread of the frame pipeline (kLaneThreadBytes), as the reference does.
  budget.add(std::string(integrator_name(scene.integrator)), run_bytes(scene, scene.integrator) + kLaneThreadBytes);
  if (pictures.final_state) budget.add("final state", final_state_bytes(scene, scene.integrator));
  if (look.reference) {
    budget.add("reference " + look.reference->name(), run_bytes(scene, look.reference->kind) + kLaneThreadBytes);
    budget.add("reference check", run_bytes(scene, look.reference->kind) + kLaneThreadBytes);  // (reference_stand.h)
    if (pictures.targets)
      budget.add("reference positions at the run's times",
                 reference_positions_bytes(scene, {scene.dt}, *pictures.targets,
                                           reference_queue_capacity(scene.cloth.nx * scene.cloth.ny, {scene.dt})));
  }
  if (pictures.rendering) {
    // The render target, the frame and one more for the PNG writer (peaks: BENCHMARKS.md).
    budget.add("renderer " + std::to_string(w) + "x" + std::to_string(h),
               kRendererBytes + render_bytes(w, h, look.samples) + 4.0 * w * h * 2);
    if (look.color != FieldKind::None && !look.color_range)
      budget.add("the first second, held for the colour scale",
                 held_frames_bytes(scene, 1, std::min(1.0, scene.duration) * scene.render.fps + 1.0));
  }
  if (pictures.video) budget.add("encoder", encoder_bytes(w, h));
  if (pictures.export_format) budget.add("export", export_bytes(scene, *pictures.export_format));
  return budget;
}

}  // namespace clothsim::clip
