// FrameSink over VideoWriter: the MP4 is opened on the first frame (its size is known
// only then) as a nameless file, named by finish().
#include <memory>
#include <optional>

#include "frame_sink.h"
#include "clip/common/cli_common.h"
#include "render/video/video_writer.h"

namespace clothsim::clip {

namespace {

class VideoSink final : public FrameSink {
 public:
  VideoSink(std::string path, const VideoOptions& options) : path_(std::move(path)) {
    options_.fps = options.fps;
    options_.crf = options.crf;
    options_.preset = options.preset;
    try {
      validate_video_options(options_);
    } catch (const std::invalid_argument& e) {
      throw UsageError("--video " + path_ + ": " + e.what());
    }
    // Fail now, not after minutes of simulation, when the file cannot be created.
    require_writable_parent(path_, "--video");
  }

  void add(int /*index*/, double /*t*/, const Image& frame) override {
    try {
      if (!writer_) writer_.emplace(path_, frame.width, frame.height, options_).stop_when(interrupted);
      writer_->write(frame);
    } catch (const VideoError& e) {
      throw RuntimeFailure(e.what());
    }
  }

  void abandon() override {
    if (!finished_) writer_.reset();  // removes the unfinished file (a finished one stays)
  }

  // The MP4 has a name only once finished: before, nothing is on disk under it.
  std::string written() const override { return finished_ ? path_ : ""; }

  void finish() override {
    if (!writer_) throw RuntimeFailure(path_ + ": no frames to encode");
    try {
      writer_->finish();
      finished_ = true;
    } catch (const VideoError& e) {
      // The drain abandoned for a signal: said as the stop, naming it (the caller adds what stays).
      if (interrupted()) throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + " while encoding " + path_);
      throw RuntimeFailure(e.what());
    }
  }

 private:
  std::string path_;
  VideoWriterOptions options_;
  std::optional<VideoWriter> writer_;  // destroyed unfinished: removes its temporary
  bool finished_ = false;
};

}  // namespace

std::unique_ptr<FrameSink> make_video_sink(const std::string& path, const VideoOptions& options) {
  return std::make_unique<VideoSink>(path, options);
}

}  // namespace clothsim::clip
