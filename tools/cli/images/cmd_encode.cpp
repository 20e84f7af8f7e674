// clothsim encode DIR... [--layout auto] [--labels a,b,...] -o FILE.mp4 [--fps N] [--crf Q] [--preset P]
//
// Assembles PNG sequences made elsewhere (frame_00000.png, frame_00001.png ... in one
// directory per tile, as `--frames` writes them) into one tiled, labelled clip.
//
// Every input is checked before the first frame is encoded: each directory holds an
// unbroken sequence from frame_00000.png, every PNG of one sequence has the same size
// (read from the PNG header, 24 bytes, so the check costs milliseconds), the layout holds
// the tiles, the output's directory is writable. Sequences may differ in length: the clip
// is as long as the longest, and a shorter sequence holds its last frame (as a diverged
// run does in `compare`), which the summary line says. Sequences may differ in size: each
// tile is centred in a cell of the largest size.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/memory_budget.h"
#include "render/png_io.h"
#include "render/video/tiling.h"
#include "render/video/video_writer.h"

namespace clothsim::cli {

namespace {

namespace fs = std::filesystem;

struct EncodeArgs {
  std::vector<std::string> dirs;
  std::string layout = "auto";
  std::string labels;
  std::string output;
  double fps = 30.0;
  int crf = VideoWriterOptions{}.crf;
  std::string preset = VideoWriterOptions{}.preset;
  std::optional<double> max_memory;  // --max-memory SIZE in bytes
};

struct Sequence {
  std::string dir;
  int frames = 0;
  int width = 0, height = 0;
  std::string frame_path(int k) const {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", k);
    return (fs::path(dir) / name).string();
  }
};

// Width and height from the PNG's header alone (render/png_io.h, as imgdiff and golden check
// read theirs): a frame is judged against --max-memory before any is decoded.
std::pair<int, int> png_header_size(const std::string& path) {
  try {
    const PngSize size = read_png_size(path);
    return {size.width, size.height};
  } catch (const PngError& e) {
    throw UsageError(std::string("encode: ") + e.what());
  }
}

// frame_NNNNN.png -> NNNNN, anything else -> -1.
int frame_number(const std::string& name) {
  if (name.size() != 15 || name.compare(0, 6, "frame_") != 0 || name.compare(11, 4, ".png") != 0)
    return -1;
  int k = 0;
  for (int i = 6; i < 11; ++i) {
    if (name[i] < '0' || name[i] > '9') return -1;
    k = k * 10 + (name[i] - '0');
  }
  return k;
}

Sequence scan_sequence(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw UsageError("encode: " + dir + ": no such directory");
  if (!fs::is_directory(dir, ec)) throw UsageError("encode: " + dir + ": not a directory");
  std::vector<int> numbers;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const int k = frame_number(entry.path().filename().string());
    if (k >= 0) numbers.push_back(k);
  }
  if (ec) throw UsageError("encode: " + dir + ": cannot list (" + ec.message() + ")");
  if (numbers.empty())
    throw UsageError("encode: " + dir + ": no frames (expected frame_00000.png, frame_00001.png, ...)");
  std::sort(numbers.begin(), numbers.end());
  Sequence seq;
  seq.dir = dir;
  for (std::size_t i = 0; i < numbers.size(); ++i)
    if (numbers[i] != static_cast<int>(i))
      throw UsageError("encode: " + seq.frame_path(static_cast<int>(i)) + " is missing (the sequence has " +
                       std::to_string(numbers.size()) + " frames up to frame_" +
                       std::to_string(numbers.back()) + ")");
  seq.frames = static_cast<int>(numbers.size());
  std::tie(seq.width, seq.height) = png_header_size(seq.frame_path(0));
  for (int k = 1; k < seq.frames; ++k) {
    const auto [w, h] = png_header_size(seq.frame_path(k));
    if (w != seq.width || h != seq.height)
      throw UsageError("encode: " + seq.frame_path(k) + " is " + std::to_string(w) + "x" +
                       std::to_string(h) + ", but frame_00000.png is " + std::to_string(seq.width) +
                       "x" + std::to_string(seq.height));
  }
  return seq;
}

std::string dir_label(const std::string& dir) {
  fs::path p = fs::path(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();  // "frames/rk4/" -> "rk4"
  return p.filename().string();
}

// --labels (one per directory, or the directories' names) and --layout, checked.
GridLayout check_labels_and_layout(const EncodeArgs& args, std::vector<std::string>& labels) {
  if (!args.labels.empty()) {
    labels = split_list(args.labels);
    if (labels.size() != args.dirs.size())
      throw UsageError("encode: --labels has " + std::to_string(labels.size()) + " names for " +
                       std::to_string(args.dirs.size()) + " directories");
  } else {
    for (const auto& dir : args.dirs) labels.push_back(dir_label(dir));
  }
  GridLayout layout;
  try {
    layout = parse_layout(args.layout, static_cast<int>(args.dirs.size()));
  } catch (const LayoutError& e) {
    throw UsageError(std::string("encode: --layout: ") + e.what());
  }
  return layout;
}

// One decoded PNG per tile, the composed frame and the encoder, before any of them exists.
void check_encode_budget(const EncodeArgs& args, const std::vector<Sequence>& seqs, const TileGrid& grid) {
  MemoryBudget budget;
  double tiles = 0.0;
  for (const Sequence& s : seqs) tiles += 4.0 * s.width * s.height;
  budget.add("tiles", tiles);
  budget.add("frame " + std::to_string(grid.width()) + "x" + std::to_string(grid.height()),
             4.0 * grid.width() * grid.height());
  budget.add("encoder", encoder_bytes(grid.width(), grid.height()));
  budget.set_remedy("encode smaller frames");
  budget.check("encode " + args.output, args.max_memory);
}

int run_encode(const EncodeArgs& args) {
  install_interrupt_handler();
  // 1. Everything that can be wrong with the command, before any encoding.
  VideoWriterOptions video{args.fps, args.crf, args.preset};
  try {
    validate_video_options(video);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("encode: ") + e.what());
  }
  std::vector<std::string> labels;
  const GridLayout layout = check_labels_and_layout(args, labels);
  std::vector<PathRole> inputs;
  for (const std::string& dir : args.dirs) inputs.push_back({dir, "input directory", true});
  refuse_clashing_paths(inputs, {{args.output, "-o/--output"}});
  require_writable_parent(args.output, "-o/--output");

  std::vector<Sequence> seqs;
  int length = 0, cell_w = 0, cell_h = 0;
  for (const auto& dir : args.dirs) {
    seqs.push_back(scan_sequence(dir));
    length = std::max(length, seqs.back().frames);
    cell_w = std::max(cell_w, seqs.back().width);
    cell_h = std::max(cell_h, seqs.back().height);
  }
  const TileGrid grid(layout, cell_w, cell_h);
  check_encode_budget(args, seqs, grid);

  // 2. Stream: read one PNG per tile, compose, encode; nothing accumulates.
  std::optional<VideoWriter> writer;
  try {
    writer.emplace(args.output, grid.width(), grid.height(), video).stop_when(interrupted);
  } catch (const VideoError& e) {
    throw RuntimeFailure(e.what());
  }
  std::vector<Image> tiles(seqs.size());
  std::vector<const Image*> tile_ptrs;
  for (const auto& t : tiles) tile_ptrs.push_back(&t);
  Image frame;
  std::optional<Progress> progress;
  progress.emplace("encode", length, "frames");
  for (int k = 0; k < length; ++k) {
    if (interrupted()) {
      writer.reset();  // removes the temporary
      progress.reset();
      throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + " at frame " + std::to_string(k) +
                           " of " + std::to_string(length) + "; " + what_stays({}, {args.output}));
    }
    for (std::size_t i = 0; i < seqs.size(); ++i) {
      if (k >= seqs[i].frames) continue;  // holds its last frame
      tiles[i] = read_png(seqs[i].frame_path(k));
      if (tiles[i].width != seqs[i].width || tiles[i].height != seqs[i].height)
        throw UsageError("encode: " + seqs[i].frame_path(k) + " changed size while encoding");
    }
    grid.compose(tile_ptrs, labels, frame);
    try {
      writer->write(frame);
    } catch (const VideoError& e) {
      throw RuntimeFailure(e.what());
    }
    progress->update(k + 1);
  }
  try {
    writer->finish();
  } catch (const VideoError& e) {
    if (interrupted())
      throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + " while finishing the clip; " +
                           what_stays({}, {args.output}));
    throw RuntimeFailure(e.what());
  }
  progress.reset();

  std::string held;
  for (const auto& s : seqs)
    if (s.frames < length)
      held += "; " + s.dir + " holds its last frame after " + std::to_string(s.frames) + " frames";
  if (!quiet()) std::fprintf(stderr, "encode: wrote %s: %d frames of %dx%d at %g fps (%dx%d tiles)%s\n",
               args.output.c_str(), length, writer->encoded_width(), writer->encoded_height(),
               args.fps, layout.columns, layout.rows, held.c_str());
  return kOk;
}

}  // namespace

void add_encode_command(CLI::App& app, Command& command) {
  auto args = std::make_shared<EncodeArgs>();
  auto* sub = app.add_subcommand(
      "encode",
      "Assemble PNG sequences (frame_00000.png ... in one directory per tile) into a tiled,\n"
      "labelled H.264 MP4. A shorter sequence holds its last frame until the longest ends.");
  sub->add_option("dirs", args->dirs, "One directory of frame_NNNNN.png per tile")->required();
  sub->add_option("--layout", args->layout,
                  "COLUMNSxROWS: 2x2, 4x1 (side by side), 1x4 (stacked), Nx1, 1xN or auto")
      ->capture_default_str();
  sub->add_option("--labels", args->labels,
                  "Comma-separated tile labels (default: directory names; an empty one: no label)");
  sub->add_option("-o,--output", args->output, "Output file (.mp4)")->required();
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  sub->add_option("--fps", args->fps, "Frames per second")->capture_default_str();
  sub->add_option("--crf", args->crf, "x264 quality: 0 lossless .. 51 worst (18-23 typical)")
      ->capture_default_str();
  sub->add_option("--preset", args->preset, "x264 preset, ultrafast .. veryslow")->capture_default_str();
  add_max_memory_option(sub, args->max_memory);
  sub->callback([&command, args] { command = [args] { return run_encode(*args); }; });
}

}  // namespace clothsim::cli
