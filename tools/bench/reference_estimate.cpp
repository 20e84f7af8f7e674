// The adaptive reference's estimated error against its true error (study/reference.h), frame by
// frame: compare's reference (dopri5 at 1e-7, checked at 1e-8) beside a solve far tighter that
// stands for the truth (1e-12 by default), on a scene and its --set. Prints the ratio of the
// estimate so far (what a tile and the table print) to the served solve's largest error so far,
// its range over the frames, and each solve's work. BENCHMARKS.md, "Contact and the reference (issue 32)".
//
//   reference_estimate SCENE.yaml [--set KEY=VALUE]... [--until T] [--truth TOL] [--fps F]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "study/reference.h"

int main(int argc, char** argv) {
  using namespace clothsim;
  if (argc < 2) {
    std::fprintf(stderr, "usage: reference_estimate SCENE.yaml [--set KEY=VALUE]... [--until T] [--truth TOL] [--fps F]\n");
    return 2;
  }
  std::vector<std::string> sets;
  double until = 2.5, truth_tol = 1e-12, fps = 30.0;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--set")) sets.push_back(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--until")) until = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--truth")) truth_tol = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--fps")) fps = std::atof(argv[i + 1]);
    else return std::fprintf(stderr, "reference_estimate: unknown option %s\n", argv[i]), 2;
  }
  const Model model = build_model(load_scene(argv[1], sets));
  analysis::AdaptiveReference ref(model);
  analysis::AdaptiveSolve truth(model, truth_tol);
  double true_error = 0.0, lo = 1e300, hi = 0.0, lo_t = 0.0, hi_t = 0.0;
  const int frames = static_cast<int>(until * fps + 0.5);
  for (int f = 1; f <= frames; ++f) {
    const double t = f / fps;
    if (!ref.advance_to(t) || !truth.advance_to(t)) return std::fprintf(stderr, "diverged at t = %g s\n", t), 1;
    true_error = std::max(true_error, analysis::largest_particle_distance(model, ref.state(), truth.state()));
    const double ratio = ref.estimated_error() / true_error;
    if (ratio < lo) lo = ratio, lo_t = t;
    if (ratio > hi) hi = ratio, hi_t = t;
    if (f % static_cast<int>(fps / 2) == 0)
      std::printf("t %.3f s: estimate %.3g m, true %.3g m, ratio %.2f\n", t, ref.estimated_error(), true_error, ratio);
  }
  std::printf("%d particles to t = %g s, %d frames: estimate / true error from %.2f (t = %.3f s) to %.2f (t = %.3f s); "
              "at the end estimate %.3g m, true %.3g m\n",
              model.num_particles, until, frames, lo, lo_t, hi, hi_t, ref.estimated_error(), true_error);
  std::printf("work: served and check %lld force evaluations (%lld steps served), truth at %g %lld steps\n",
              static_cast<long long>(ref.totals().force_evals), static_cast<long long>(ref.totals().steps), truth_tol,
              static_cast<long long>(truth.steps()));
  return lo >= 1.0 && hi <= 3.0 ? 0 : 1;
}
