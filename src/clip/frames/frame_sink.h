// Where rendered frames go: a PNG sequence, an MP4, or both. `run` and `compare` stream
// frames into sinks as they are rendered, so memory stays flat in clip length.
#pragma once

#include <memory>
#include <string>

#include "render/image.h"
#include "render/png_io.h"

namespace clothsim::clip {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Frame `index` (0, 1, 2...) at simulated time t. Throws RuntimeFailure on I/O errors.
  virtual void add(int index, double t, const Image& frame) = 0;
  // Completes the output (an MP4 gets its name only here: io/output_file.h). A sink
  // destroyed without finish() leaves nothing under the name.
  virtual void finish() = 0;
  // Stops without completing (a signal, another output failing): drops what is queued and
  // removes any temporary. What stays on disk after it is written()'s to say.
  virtual void abandon() = 0;
  // What this sink has on disk under its name, for the closing message of a run that stops
  // ("7 PNGs in out/run", "clip.mp4" once finished; "" for nothing). A query: it changes
  // nothing, and is meant after finish() or abandon() (a sink still writing would be counting).
  virtual std::string written() const = 0;
};

// frame_00000.png, frame_00001.png ... in `dir` (created if missing), with `meta` as tEXt
// chunks plus "t". PNGs are written on a background thread so rendering does not wait.
std::unique_ptr<FrameSink> make_png_sequence_sink(const std::string& dir, PngText meta);

struct VideoOptions {
  double fps = 30.0;
  int crf = 20;                     // x264 constant rate factor: 0 lossless .. 51 worst
  std::string preset = "veryfast";  // x264 preset
};
// An H.264 MP4 at `path`, written without a name (io/output_file.h) and named by finish().
std::unique_ptr<FrameSink> make_video_sink(const std::string& path, const VideoOptions& options);

}  // namespace clothsim::clip
