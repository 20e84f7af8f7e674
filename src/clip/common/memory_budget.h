// --max-memory: a run's estimated peak memory (src/scene/memory_estimate.h for the engine; the
// renderer and the encoder here) against a limit, checked before anything large is allocated.
// Over the limit, the command is refused (exit 2) with the estimate and what it is made of.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "export/export_path.h"
#include "scene/scene_def.h"

namespace clothsim::clip {

// "4G", "512M", "1.5G", "800MB", "2000000000" (bytes); K, M, G, T are powers of 1024.
// nullopt for anything else (negative, zero, words).
std::optional<double> parse_memory_size(const std::string& text);
// --max-memory's value (parse_memory_size), or UsageError "--max-memory: 'x' is not a size (e.g.
// 4G, 512M, 1.5G)": the CLI's option and the Python module's max_memory= keyword.
double max_memory_option(const std::string& text);
// "5.12 GB", "80 MB" (powers of 1024, three significant digits).
std::string format_bytes(double bytes);
// Half the physical memory: room for the rest of the machine (and the other jobs of a batch
// node), and far below where Linux's OOM killer would end the run without a word.
double default_memory_limit();

// Process, GL and image sizes, each rounded up from peak RSS (BENCHMARKS.md, "Memory estimate").
inline constexpr double kProcessBytes = 80.0 * 1024 * 1024;   // libraries and a tiny scene
// OSMesa / llvmpipe's own (its threads, shader cache, the context): a run's still at 320x180
// peaks at 117 MiB against 79 MiB without pictures (BENCHMARKS.md, "Memory estimate").
inline constexpr double kRendererBytes = 38.0 * 1024 * 1024;
// The renderer's buffers per pixel of its target: 4 B plus 11 B per sample (`samples`: the
// look's, 1 under fxaa or none). Fitted to peaks at 720p and 1080p with 1 and 4 samples.
double render_bytes(int width, int height, int samples);
// x264 (veryfast) and the YUV conversion of the encoded picture once its lookahead and frame
// threads are full (a clip of 2 s or more): 24 MiB plus 116 B a pixel, fitted to run --video's
// peaks at 720p and 1080p on this 2-core machine (two runs of 1080p read 441 and 463 MiB);
// x264's frame threads, hence its memory, grow with the machine's cores.
double encoder_bytes(int width, int height);

// Each lane thread of a frame pipeline beyond the Run itself: glibc's per-thread malloc arena
// and the thread's stack pages, as far as they are touched (compare --summary on the drape,
// four lane threads: 79.8 MiB peak against 79.0 for run without pictures).
inline constexpr double kLaneThreadBytes = 0.5 * 1024 * 1024;

// Lane frames held back while a colour scale is chosen from the first second's data
// (frame_pipeline.h): `frames` targets of `lanes` lanes, each a picture's geometry (positions,
// normals, grid coordinates, triangles: 56 B per particle), the field (4 B) and double
// positions for the error (24 B): 84 B per particle, counted as 96.
double held_frames_bytes(const SceneDef& scene, std::size_t lanes, double frames);

// --export of one lane: the lane's queued frames each carry every body's x and v (48 B a
// particle, kLaneQueueCapacity frames and the one being written), and the frame being written
// its mesh (points, triangles, fields) and, for a text format, its text. Fitted to run
// --export's peaks over run's without, on the drape at 256², 512² and 1024² (symplectic Euler,
// 0.07-0.2 s; BENCHMARKS.md, "Memory estimate"): OBJ, PLY and PC2 at most 321 B a particle
// (PC2 238-301, PLY 296, OBJ 280-321), VTP's ASCII text at most 569 B; counted as 360 and 600,
// since at 1024² over 0.2 s run's own peak is 5 % above its estimate (625 MiB against 592).
double export_bytes(const SceneDef& scene, ExportFormat format);

// Refuses (UsageError, exit 2) a scene file whose parse would pass `limit`: yaml-cpp's node
// tree, estimated from the text (scene/parse_estimate.h) before it is parsed. A tree of at most
// kSmallSceneTreeBytes is the process's own (kProcessBytes: measured 76-78 MiB with one).
inline constexpr double kSmallSceneTreeBytes = 2.0 * 1024 * 1024;
void check_parse_budget(const std::string& path, const std::optional<double>& limit);
// A scene that is not a regular file (a FIFO, a device, /dev/stdin) can be read only once: its
// text, read here and bounded by a quarter of `limit` (/dev/zero is refused at that size, not
// grown into), then judged as a file's. nullopt for a regular file, a directory or a missing
// name (the parser says what is wrong). A signal while a FIFO waits for its writer stops it.
std::optional<std::string> read_scene_stream(const std::string& path, const std::optional<double>& limit);
// The scene (scene_parser.h's load_scene, or parse_scene on a stream's text) with `overrides`,
// its parse checked against `limit` first.
SceneDef load_scene_within(const std::string& path, const std::vector<std::string>& overrides,
                           const std::optional<double>& limit, bool bound_run = true);

// The address-space limit (ulimit -v, RLIMIT_AS) in bytes; nullopt when unlimited. The
// address space the process has mapped so far (its libraries, its heap, touched or not).
std::optional<double> address_space_limit();
double address_space_mapped();
// Address space a command maps beyond its resident estimate: the threads' stacks and glibc's
// per-thread malloc arenas, reserved but mostly untouched. Measured as VmPeak less what was
// mapped at the check less the estimate: 123-134 MB for `run` at 256x256 and 512x512 without
// pictures; a renderer's (llvmpipe's) threads reserve more, which its arenas give up under a
// limit, and an allocation that still fails is said on one line (main.cpp).
inline constexpr double kAddressSpaceReserve = 256.0 * 1024 * 1024;

class MemoryBudget {
 public:
  MemoryBudget();  // starts with the process itself
  void add(std::string what, double bytes) { parts_.emplace_back(std::move(what), bytes); }
  double total() const;
  // Throws UsageError when total() exceeds `limit` (the default when nullopt): "SOURCE: needs
  // an estimated 5.6 GB (model 1.3 GB, implicit_euler 4.3 GB, ...), more than --max-memory 2 GB",
  // and RuntimeFailure (exit 1, the machine's limit) when what is still to be mapped would pass
  // the address-space limit (ulimit -v).
  void check(const std::string& source, const std::optional<double>& limit) const;
  // What the message suggests before raising the limit.
  void set_remedy(std::string remedy) { remedy_ = std::move(remedy); }

 private:
  std::string remedy_ = "use fewer particles or a smaller picture";
  std::vector<std::pair<std::string, double>> parts_;
};

}  // namespace clothsim::clip
