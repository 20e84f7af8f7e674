// Renderer throughput: frames/s of render + readback (MSAA resolve, glFinish, glReadPixels,
// flip, overlay text) for the shipped drape (25 x 25, draped over its ball at t = 1.5 s) and
// for the same scene with a 256 x 256 sheet (at t = 0: flat, above the ball), and ms per PNG
// write of a rendered 1280x720 frame at each fast zlib level. "CPU" is the process's CPU time
// (all llvmpipe threads): on a busy machine it is steadier than wall time, and wall time on an
// idle machine is no less than CPU / cores.
//   build/tools/bench/render_benchmarks
//   LP_NUM_THREADS=1 build/tools/bench/render_benchmarks   # llvmpipe rasterizer threads
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "bench_models.h"
#include "clip/frames/overlay_text.h"
#include "clip/frames/picture_options.h"
#include "core/run/simulation.h"
#include "render/fxaa.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "view/snapshot.h"

namespace clothsim {
namespace {

// The scene's frame at time t, as `clothsim run --frames` renders it (overlay included).
RenderFrame scene_frame(int n, double t, int width, int height, int samples) {
  const SceneDef scene = bench::drape_scene(n);
  const Model model = build_model(scene);
  Run run(model, model.integrator, model.dt);
  run.advance_to(t);
  RenderFrame frame = make_render_frame(model, run.state(), scene.render);
  frame.overlay_lines = clip::overlay_lines(model, model.integrator, model.dt, run.state().t);
  frame.width = width;
  frame.height = height;
  frame.samples = samples;
  return frame;
}

Renderer& renderer() {
  static Renderer r;  // one context, created once (about 50 ms), as a run creates it once
  return r;
}

void render_loop(benchmark::State& st, const RenderFrame& frame) {
  Renderer& r = renderer();
  r.render(frame);  // first frame: FBOs made, shader variants compiled
  for (auto _ : st) {
    Image image = r.render(frame);
    benchmark::DoNotOptimize(image.rgba.data());
  }
  st.counters["frames/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  st.SetLabel(std::to_string(frame.width) + "x" + std::to_string(frame.height) + " " +
              std::to_string(frame.samples) + "x MSAA" + (frame.fxaa ? " + FXAA" : "") + ", " +
              std::to_string(frame.cloth_triangles.size() / 3) + " cloth triangles");
}

// Arg: MSAA samples.
void BM_RenderDrape25_1280x720(benchmark::State& st) {
  render_loop(st, scene_frame(25, 1.5, 1280, 720, static_cast<int>(st.range(0))));
}
BENCHMARK(BM_RenderDrape25_1280x720)->Arg(4)->Arg(1)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_RenderSheet256_1280x720(benchmark::State& st) {
  render_loop(st, scene_frame(256, 0.0, 1280, 720, static_cast<int>(st.range(0))));
}
BENCHMARK(BM_RenderSheet256_1280x720)->Arg(4)->Arg(1)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

// One tile of `clothsim compare`'s default 2x2 clip.
void BM_RenderDrape25_640x360(benchmark::State& st) {
  render_loop(st, scene_frame(25, 1.5, 640, 360, static_cast<int>(st.range(0))));
}
BENCHMARK(BM_RenderDrape25_640x360)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

// A tile as `compare` draws the default clip: 638 x 358, the auto camera framing the cloth and
// the ball (render.camera: auto), the drape at 1.5 s. Arg: MSAA samples, or 0 for FXAA over
// one sample (render.antialias: fxaa, compare's default).
void BM_RenderCompareTile(benchmark::State& st) {
  const int arg = static_cast<int>(st.range(0));
  RenderFrame frame = scene_frame(25, 1.5, 638, 358, std::max(arg, 1));
  frame.camera = clip::auto_camera(bench::drape_sheet(25), bench::drape_scene(25).render, 638.0 / 358.0);
  frame.fxaa = arg == 0;
  render_loop(st, frame);
}
BENCHMARK(BM_RenderCompareTile)->Arg(0)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

// FXAA alone on the compare tile above rendered with one sample, over the whole tile (every
// pixel a candidate: more than the renderer's drawn region and mask give it).
void BM_FxaaCompareTile(benchmark::State& st) {
  RenderFrame frame = scene_frame(25, 1.5, 638, 358, 1);
  frame.camera = clip::auto_camera(bench::drape_sheet(25), bench::drape_scene(25).render, 638.0 / 358.0);
  const Image aliased = renderer().render(frame);
  Image image;
  for (auto _ : st) {
    st.PauseTiming();
    image = aliased;
    st.ResumeTiming();
    fxaa(image, 0, 0, image.width, image.height, nullptr);
    benchmark::DoNotOptimize(image.rgba.data());
  }
}
BENCHMARK(BM_FxaaCompareTile)->Unit(benchmark::kMicrosecond);

// Arg: zlib level.
void BM_WritePng_1280x720(benchmark::State& st) {
  const Image image = renderer().render(scene_frame(25, 1.5, 1280, 720, 4));
  const std::string path = (std::filesystem::temp_directory_path() / "clothsim_render_bench.png").string();
  const int level = static_cast<int>(st.range(0));
  for (auto _ : st) write_png(path, image, {{"scene", "drape"}, {"t", "1.5"}}, level);
  st.counters["bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove(path);
}
BENCHMARK(BM_WritePng_1280x720)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace clothsim

BENCHMARK_MAIN();
