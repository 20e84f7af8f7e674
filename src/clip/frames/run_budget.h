// The estimated peak memory of a run of one lane (memory_budget.h): `run`, and `golden`, which
// runs each manifest entry as `run --still` does, so both refuse the same scene the same way.
#pragma once

#include <optional>

#include "clip/common/memory_budget.h"
#include "clip/common/plan_parts.h"  // TargetPlan
#include "clip/frames/picture_options.h"
#include "scene/scene_def.h"

namespace clothsim::clip {

// What the run makes besides its state: pictures of `width` x `height` (frames, a video, a
// still), and whether they are encoded to a video.
struct RunPictures {
  bool rendering = false;
  int width = 0, height = 0;  // pixels
  bool video = false;
  bool final_state = false;   // the last state is kept to write it (run --state)
  std::optional<ExportFormat> export_format;  // --export's, when given
  // The times the run stands at, for the positions the reference holds while a target waits
  // (memory_budget.h, reference_positions_bytes); null where the caller has no plan yet.
  const TargetPlan* targets = nullptr;
};

// The process, the Model, the scene's integrator on its lane thread, the reference lane of
// `look` (--color error) and the positions it holds for the targets, and with pictures the renderer, its frames queued for the PNG
// writer, the first second held for a colour scale from the data, the encoder, and --export's
// frames and mesh.
MemoryBudget run_budget(const SceneDef& scene, const PictureLook& look, const RunPictures& pictures);

}  // namespace clothsim::clip
