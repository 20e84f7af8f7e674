// clothsim imgdiff A.png B.png: how far apart two images are, by the same measure the
// golden-image tests use (render/image_diff.h). Exit 0 within tolerance, 1 outside it,
// 2 for bad usage (a missing or corrupt PNG, different sizes).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/memory_budget.h"
#include "render/image_diff.h"
#include "render/png_io.h"

namespace clothsim::cli {
namespace {

struct ImgdiffOptions {
  std::string a, b;
  std::string diff_path;
  DiffTolerance tolerance;
  std::optional<double> max_memory;  // --max-memory
};

// A missing or corrupt PNG is the user's input, a usage error ("cannot read A.png: not a PNG file").
template <class Read>
auto read_input(const Read& read) {
  try {
    return read();
  } catch (const PngError& e) {
    throw UsageError(e.what());
  }
}

std::string size_text(const PngSize& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

// From the headers alone, before decoding: equal sizes, and the decoded images (4 bytes a pixel
// each, and the difference image) within --max-memory.
void check_inputs(const ImgdiffOptions& o) {
  const PngSize a = read_input([&] { return read_png_size(o.a); });
  const PngSize b = read_input([&] { return read_png_size(o.b); });
  if (a.width != b.width || a.height != b.height)
    throw UsageError("imgdiff: " + o.a + " is " + size_text(a) + " but " + o.b + " is " + size_text(b));
  const double image_bytes = 4.0 * a.width * a.height;
  MemoryBudget budget;
  budget.add("two " + size_text(a) + " images", 2 * image_bytes);
  if (!o.diff_path.empty()) budget.add("the difference image", image_bytes);
  budget.set_remedy("compare smaller images");
  budget.check(o.a, o.max_memory);
}

// CLI11's range check lets NaN through (every comparison with it is false).
void check_tolerances(const ImgdiffOptions& o) {
  if (std::isnan(o.tolerance.max_rms)) throw UsageError("--max-rms: must be a number from 0 to 255, got nan");
  if (std::isnan(o.tolerance.max_over_fraction)) throw UsageError("--max-over: must be a number from 0 to 1, got nan");
}

int imgdiff_command(const ImgdiffOptions& o) {
  check_tolerances(o);
  refuse_clashing_paths({{o.a, "input A"}, {o.b, "input B"}}, {{o.diff_path, "-o/--output"}});
  if (!o.diff_path.empty()) require_png_name(o.diff_path, "-o/--output");
  if (!o.diff_path.empty()) require_writable_parent(o.diff_path, "-o/--output");
  check_inputs(o);
  const Image a = read_input([&] { return read_png(o.a); });
  const Image b = read_input([&] { return read_png(o.b); });

  const DiffStats stats = compare_images(a, b, o.tolerance.pixel_threshold);
  const bool pass = within_tolerance(stats, o.tolerance);
  std::printf("%s vs %s (%dx%d)\n", o.a.c_str(), o.b.c_str(), a.width, a.height);
  std::printf("  rms difference     %.4f  (tolerance %g)\n", stats.rms, o.tolerance.max_rms);
  std::printf("  max difference     %d\n", stats.max);
  std::printf("  pixels past %-3d    %.4f%%  (tolerance %g%%)\n", o.tolerance.pixel_threshold,
              100.0 * stats.over_fraction, 100.0 * o.tolerance.max_over_fraction);
  std::printf("%s\n", pass ? "within tolerance" : "DIFFERENT: outside tolerance");
  if (!o.diff_path.empty()) {
    try {
      write_png(o.diff_path, diff_image(a, b));
    } catch (const PngError& e) {
      throw RuntimeFailure(e.what());
    }
    std::printf("diff image: %s\n", o.diff_path.c_str());
  }
  return pass ? kOk : 1;
}

}  // namespace

void add_imgdiff_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<ImgdiffOptions>();
  CLI::App* sub = app.add_subcommand(
      "imgdiff", "Compare two PNG images (golden-image tests): RMS and max per-channel difference, "
                 "share of pixels past a threshold; exit 0 within tolerance, 1 outside, 2 bad input");
  sub->add_option("A", o->a, "First image (e.g. the golden one)")->required();
  sub->add_option("B", o->b, "Second image (e.g. the new render)")->required();
  sub->add_option("-o,--output,--diff", o->diff_path, "Write an amplified difference image here (PNG)")
      ->type_name("FILE.png");
  add_no_overwrite_option(sub);
  add_max_memory_option(sub, o->max_memory);
  sub->add_option("--threshold", o->tolerance.pixel_threshold,
                  "A pixel differs when some channel differs by more than this (0-255)")
      ->check(CLI::Range(0, 255))
      ->capture_default_str();
  sub->add_option("--max-rms", o->tolerance.max_rms, "Largest RMS difference (0-255 scale) that passes")
      ->check(CLI::Range(0.0, 255.0))
      ->capture_default_str();
  sub->add_option("--max-over", o->tolerance.max_over_fraction,
                  "Largest share of differing pixels that passes (0-1)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  sub->callback([o, &command] { command = [o] { return imgdiff_command(*o); }; });
}

}  // namespace clothsim::cli
