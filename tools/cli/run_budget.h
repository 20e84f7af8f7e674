// The estimated peak memory of a run of one lane (memory_budget.h): `run`, and `golden`, which
// runs each manifest entry as `run --still` does, so both refuse the same scene the same way.
#pragma once

#include "memory_budget.h"
#include "picture_options.h"
#include "scene_def.h"

namespace clothsim::cli {

// What the run makes besides its state: pictures of `width` x `height` (frames, a video, a
// still), and whether they are encoded to a video.
struct RunPictures {
  bool rendering = false;
  int width = 0, height = 0;  // pixels
  bool video = false;
};

// The process, the Model, the scene's integrator on its lane thread, the reference lane of
// `look` (--color error), and with pictures the renderer, its frames queued for the PNG
// writer, the first second held for a colour scale from the data, and the encoder.
MemoryBudget run_budget(const SceneDef& scene, const PictureLook& look, const RunPictures& pictures);

}  // namespace clothsim::cli
