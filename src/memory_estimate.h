// What a scene will cost in memory before any of it is allocated, so that a scene too big for
// the machine (particles: [2048, 2048] needs about 5 GB for implicit Euler) is refused with
// the estimate instead of swapping or dying of bad_alloc minutes in.
//
// Coefficients from GNU time's peak RSS on the drape scene (all three spring types, about 6
// springs per particle) at 128^2, 256^2 and 512^2 particles (BENCHMARKS.md, "Memory
// estimate"): the Model 96 B per particle and 40 B per spring, what its arrays hold rounded
// up (measured 312 B per particle with its springs, estimated 336), 64 B per scripted action;
// a run's state and scratch 192 B per particle for
// the explicit family (RK4's stages, the worst of them: measured 192 B over the Model,
// symplectic Euler 73 B); implicit Euler adds its sparse system, 256 B per particle and 128 B
// per spring (measured 1 344 B per particle in all, estimated 1 552, in runs that did not
// factor; implicit_euler's reused Newton matrix and line guess, State::implicit_lin_* and
// implicit_dv_before, then added 147 B per particle at 512^2 (706 against 667 MB peak, GNU
// time, side by side), which the 208 B of headroom covers; the SIMD passes' diagonal copies
// and kept lengths (branch simd-assembly) about 200 B more, 757 348 against 706 084 kB peak at
// 512^2, under the 982 MB estimated there; but at 2048^2 main itself peaked at 10.6 GB, above
// the 6.64 GB estimated: to be re-measured), plus the sparse factor a step may build:
// 80 B x 8 log2(P) per particle (measured 27-116 blocks of 76 B per particle at 25^2..300^2),
// never more than the solver's 512 MiB cap. A sphere costs about 4 kB, mostly its YAML tree while the file is read. The estimate
// errs high on purpose; issue 12 measured 5.1 GB at 2048^2 for implicit Euler, estimated here
// 6.6 GB with the factor's cap.
#pragma once

#include <cstdint>

#include "scene_def.h"

namespace clothsim {

// Springs the scene's cloth will have (structural, shear and bend, those it declares).
std::int64_t spring_count(const ClothDef& cloth);

// Bytes of the Model built from `scene`: never less than its arrays hold (the fuzz target,
// tests/fuzz/scene_fuzz.h, checks it on every scene it builds).
double model_bytes(const SceneDef& scene);
// Bytes of one run of `kind` on that Model (state, integrator scratch, implicit system).
double run_bytes(const SceneDef& scene, IntegratorKind kind);

}  // namespace clothsim
