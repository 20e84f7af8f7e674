// What a scene will cost in memory before any of it is allocated, so that a scene too big for
// the machine is refused with the estimate instead of swapping or dying of bad_alloc minutes in.
// The Model's coefficients here, each method's in its registry row (core/integrators/
// method_memory.h); all from peak RSS at several sizes, rounded up so the
// estimate errs high: BENCHMARKS.md, "Memory estimate", has the measurements.
#pragma once

#include <cstdint>

#include "scene_def.h"

namespace clothsim {

// Springs the scene's cloth will have (structural, shear and bend, those it declares).
std::int64_t spring_count(const ClothDef& cloth);

// Bytes of the Model built from `scene`: never less than its arrays hold (the fuzz target,
// tests/fuzz/scene_fuzz.h, checks it on every scene it builds).
double model_bytes(const SceneDef& scene);
// Bytes of one run of `kind` on that Model (state, integrator scratch, implicit system, the
// sparse factor implicit_euler may build and projective dynamics' prefactored matrix).
double run_bytes(const SceneDef& scene, IntegratorKind kind);
// Bytes of the final state a run of `kind` keeps to write it (run --state): a State, with
// implicit_euler's warm start.
double final_state_bytes(const SceneDef& scene, IntegratorKind kind);

}  // namespace clothsim
