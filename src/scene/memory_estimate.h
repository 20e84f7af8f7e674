// What a scene will cost in memory before any of it is allocated, so that a scene too big for
// the machine (particles: [2048, 2048] needs about 8 GB for implicit Euler) is refused with
// the estimate instead of swapping or dying of bad_alloc minutes in.
//
// Coefficients from GNU time's peak RSS on the drape scene (all three spring types, about 6
// springs per particle) at 128^2, 256^2 and 512^2 particles (BENCHMARKS.md, "Memory
// estimate"): the Model 96 B per particle and 40 B per spring, what its arrays hold rounded
// up (measured 312 B per particle with its springs, estimated 336), 64 B per scripted action;
// a run's state and scratch 192 B per particle for
// the explicit family (RK4's stages, the worst of them: measured 192 B over the Model,
// symplectic Euler 73 B); implicit Euler adds its sparse system, its reused Newton matrix's
// inputs and the SIMD passes' copies, 480 B per particle and 144 B per spring: measured 1 356 B
// per particle over the Model at 2048^2 and 1 359 B at 1024^2 (GNU time, 2 steps, no factor),
// estimated 1 536; plus the sparse factor a step may build:
// 80 B x 8 log2(P) per particle (measured 27-116 blocks of 76 B per particle at 25^2..300^2),
// never more than the solver's 512 MiB cap. A sphere costs about 4 kB, mostly its YAML tree while the file is read. The estimate
// errs high on purpose: at 2048^2 implicit Euler peaks at 7.53 GB, estimated 7.89 GB with the
// factor's cap (the factor's ordering is skipped where even a factor without fill would pass
// the cap: cholesky_preconditioner.h; before that the ordering alone took the peak to 11.5 GB).
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
