// Video benchmarks: H.264 encoder throughput at 1280x720 (the default comparison clip's
// size) per x264 preset, and the cost of composing a 2x2 grid of tiles.
//
// The frames are synthetic but shaped like renders: a smooth background gradient and a
// moving checkered disc (the cloth's checker), so x264 sees flat areas, sharp edges and
// motion, not noise (which would make every preset look slow) nor a still picture
// (which would make every preset look fast).
//
//   ./video_benchmarks --benchmark_filter=Encode
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "render/video/tiling.h"
#include "render/video/video_writer.h"

namespace {

using clothsim::Image;

Image synthetic_frame(int w, int h, int k) {
  Image image(w, h);
  const double cx = w * (0.3 + 0.4 * (0.5 + 0.5 * std::sin(0.07 * k)));
  const double cy = h * (0.5 + 0.2 * std::cos(0.05 * k));
  const double r = 0.25 * h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = image.pixel(x, y);
      const double dx = x - cx, dy = y - cy;
      if (dx * dx + dy * dy < r * r) {
        const bool dark = ((static_cast<int>((dx + 4 * k) / 24) + static_cast<int>(dy / 24)) & 1) != 0;
        p[0] = dark ? 40 : 60, p[1] = dark ? 90 : 130, p[2] = dark ? 180 : 230;
      } else {
        p[0] = static_cast<std::uint8_t>(200 + 37 * y / h);
        p[1] = static_cast<std::uint8_t>(205 + 30 * y / h);
        p[2] = static_cast<std::uint8_t>(215 + 25 * x / w);
      }
      p[3] = 255;
    }
  return image;
}

const std::vector<Image>& frames_720p() {
  static const std::vector<Image> frames = [] {
    std::vector<Image> out;
    for (int k = 0; k < 30; ++k) out.push_back(synthetic_frame(1280, 720, k));
    return out;
  }();
  return frames;
}

// One iteration = a 60-frame clip, opened, encoded, drained and renamed: the encoder's
// look-ahead flush is part of what a clip costs. Reported as frames per second.
void BM_Encode720p(benchmark::State& state, const char* preset) {
  const auto& frames = frames_720p();
  const std::string path =
      (std::filesystem::temp_directory_path() / ("clothsim_video_bench_" + std::string(preset) + ".mp4")).string();
  constexpr int kFrames = 60;
  for (auto _ : state) {
    clothsim::VideoWriter writer(path, 1280, 720, clothsim::VideoWriterOptions{30.0, 20, preset});
    for (int k = 0; k < kFrames; ++k) writer.write(frames[k % frames.size()]);
    writer.finish();
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kFrames), benchmark::Counter::kIsRate);
  state.counters["bytes_per_frame"] =
      static_cast<double>(std::filesystem::file_size(path)) / kFrames;
  std::filesystem::remove(path);
}
BENCHMARK_CAPTURE(BM_Encode720p, ultrafast, "ultrafast")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Encode720p, veryfast, "veryfast")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Encode720p, medium, "medium")->Unit(benchmark::kMillisecond)->UseRealTime();

// The per-frame work of `compare` besides rendering and encoding: four 638x358 tiles into
// a 1280x720 canvas.
void BM_Compose2x2At720p(benchmark::State& state) {
  const clothsim::TileGrid grid =
      clothsim::TileGrid::fit(clothsim::GridLayout{2, 2}, 1280, 720);
  std::vector<Image> tiles;
  for (int i = 0; i < 4; ++i) tiles.push_back(synthetic_frame(grid.cell_width(), grid.cell_height(), i));
  std::vector<const Image*> ptrs;
  for (const auto& t : tiles) ptrs.push_back(&t);
  const std::vector<std::string> labels = {"explicit_euler", "implicit_euler", "midpoint", "rk4"};
  Image canvas;
  for (auto _ : state) {
    grid.compose(ptrs, labels, canvas);
    benchmark::DoNotOptimize(canvas.rgba.data());
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Compose2x2At720p)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
