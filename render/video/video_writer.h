// VideoWriter: RGBA Images in, an H.264 MP4 out, through FFmpeg's libraries
// (libavformat muxes, libavcodec + libx264 encode, libswscale converts RGBA -> YUV).
//
// Choices, and why:
//   - yuv420p: the only chroma layout every browser and phone plays back. It halves
//     chroma resolution in both directions, so the encoded picture must have even
//     width and height; odd sizes are padded by repeating the last column/row (never
//     refused), and the padding is part of the picture a player shows.
//   - BT.709, limited ("tv") range: what HD players assume for untagged video anyway;
//     the stream is tagged (matrix, primaries, transfer, range) so none has to guess,
//     and the RGB -> YUV conversion uses the same BT.709 matrix it claims.
//   - +faststart: the index (moov atom) goes to the front on finish, so a browser can
//     start playing before it has the whole file. Streamed to a pipe or device (which cannot
//     be read back), the MP4 is fragmented instead (empty_moov + frag_keyframe).
//   - CRF (constant quality) rather than a bitrate: the clip's size follows its content.
//     The x264 preset trades encode speed for size at that quality.
//   - Frames are encoded as they arrive (send_frame/receive_packet); only x264's
//     bounded look-ahead is held, so memory is flat in clip length.
//   - The file is an OutputFile (io/output_file.h), written through a custom
//     AVIOContext on its descriptor and given its name only by finish(): a crash, an
//     error, Ctrl-C or SIGKILL never leaves a truncated MP4, or any temporary, behind.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "render/image.h"

namespace clothsim {

// Every failure: "PATH: what failed: libav's reason".
struct VideoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct VideoWriterOptions {
  double fps = 30.0;                // frames per second; stored as an exact rational (29.97 -> 2997/100)
  int crf = 20;                     // x264 constant rate factor: 0 lossless .. 51 worst; ~18 looks lossless
  std::string preset = "veryfast";  // x264 preset: speed against file size at equal quality
};

// The slowest rate a stream can carry: its time base is 1/fps as a fraction of integers up
// to 100000 (a frame every 1000 s).
inline constexpr double kMinFps = 0.001;

// x264's presets, fastest first ("ultrafast" ... "placebo").
const std::vector<std::string>& x264_presets();
bool is_x264_preset(std::string_view name);
// Checks options before any work: fps in [kMinFps, 1000], crf in 0..51, a known preset.
// Throws std::invalid_argument with a one-line message naming the bad option.
void validate_video_options(const VideoWriterOptions& options);

// Encoded picture size for an image of w x h: rounded up to even (yuv420p).
int even_size(int n);

class VideoWriter {
 public:
  // Opens the encoder and a nameless file in `path`'s directory for frames of width x height
  // (odd sizes allowed). The container follows the extension (.mp4, .mov, .mkv), MP4 when
  // it is not recognised. Throws VideoError (directory not writable, encoder missing...).
  VideoWriter(const std::string& path, int width, int height, const VideoWriterOptions& options = {});
  ~VideoWriter();  // without finish(): stops, and the nameless file is dropped
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Encodes the next frame (presentation time = frames written / fps). The image must
  // be width x height as given to the constructor. Throws VideoError.
  void write(const Image& frame);
  // Drains the encoder, writes the index and names the file. Throws VideoError.
  void finish();
  // Polled between packets while finish() drains the encoder (placebo holds seconds of
  // look-ahead): true abandons the clip at once with VideoError "PATH: stopped".
  void stop_when(std::function<bool()> stop);

  int frames_written() const;
  int width() const;          // as given
  int height() const;
  int encoded_width() const;  // even, what the stream holds
  int encoded_height() const;
  const std::string& path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim
