// H.264 through libavcodec's send_frame/receive_packet API (FFmpeg >= 4), muxed by
// libavformat. See video_writer.h for the choices; this file is the plumbing.
#include "video_writer.h"

#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "io/output_file.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace clothsim {

namespace {

// libav reports details of a failure (x264's "Error setting preset", a muxer's reason)
// through av_log, not through return codes. The default callback prints every INFO line
// on stderr, which would break the CLI's "one clear line" rule, so we keep only the last
// error-level message and put it into the exception instead.
std::mutex g_log_mutex;
std::string g_last_log_error;

void capture_av_log(void* avcl, int level, const char* fmt, va_list args) {
  if (level > AV_LOG_ERROR) return;
  char line[512];
  int print_prefix = 1;
  av_log_format_line2(avcl, level, fmt, args, line, sizeof line, &print_prefix);
  std::string text(line);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::lock_guard<std::mutex> lock(g_log_mutex);
  g_last_log_error = text;
}

void install_log_capture() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_callback(capture_av_log); });
}

std::string take_log_error() {
  std::lock_guard<std::mutex> lock(g_log_mutex);
  std::string text;
  text.swap(g_last_log_error);
  return text;
}

// x264 reports a failed allocation (x264_malloc: "malloc of size N failed") through its own
// default logger, straight to stderr, not through av_log, so a failure would print two lines.
// While the encoder opens, fd 2 goes to a memory file instead: on failure its last line joins
// the one-line error; on success its text is passed on to stderr unchanged.
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    memory_ = ::memfd_create("clothsim-encoder-log", MFD_CLOEXEC);
    if (memory_ >= 0) saved_ = ::dup(STDERR_FILENO);
    if (memory_ < 0 || saved_ < 0 || ::dup2(memory_, STDERR_FILENO) < 0) restore();  // not captured
  }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  ~StderrCapture() { pass_on(); }

  // Restores stderr; returns what was written meanwhile.
  std::string release() {
    std::string text;
    if (memory_ < 0) return text;
    std::fflush(stderr);
    char buffer[4096];
    for (off_t at = 0;;) {
      const ssize_t n = ::pread(memory_, buffer, sizeof buffer, at);
      if (n <= 0) break;
      text.append(buffer, static_cast<std::size_t>(n));
      at += n;
    }
    restore();
    return text;
  }
  // Restores stderr and writes what was captured to it.
  void pass_on() {
    const std::string text = release();
    if (!text.empty()) write_all(STDERR_FILENO, text.data(), text.size());
  }
  // Restores stderr and returns the last non-empty line captured ("" when none).
  std::string last_line() {
    std::string text = release();
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
    const std::size_t start = text.find_last_of("\r\n");
    if (start != std::string::npos) text.erase(0, start + 1);
    if (text.size() > 200) text.resize(200);
    return text;
  }

 private:
  void restore() {
    if (saved_ >= 0) {
      ::dup2(saved_, STDERR_FILENO);
      ::close(saved_);
    }
    if (memory_ >= 0) ::close(memory_);
    saved_ = memory_ = -1;
  }
  int memory_ = -1, saved_ = -1;
};

// Keeps `detail` as the failure's explanation when av_log gave none.
void keep_log_error(const std::string& detail) {
  std::lock_guard<std::mutex> lock(g_log_mutex);
  if (g_last_log_error.empty()) g_last_log_error = detail;
}

std::string av_error_text(int code) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, buf, sizeof buf);
  return buf;
}

[[noreturn]] void fail(const std::string& path, const std::string& what, int code = 0) {
  std::string message = path + ": " + what;
  if (code < 0) message += ": " + av_error_text(code);
  const std::string detail = take_log_error();
  if (!detail.empty()) message += " (" + detail + ")";
  throw VideoError(message);
}

// An I/O failure says it as every output does: "cannot write PATH: File too large".
[[noreturn]] void fail_write(const std::string& path, int code) {
  take_log_error();  // the muxer's own line repeats the reason
  throw VideoError("cannot write " + path + ": " + av_error_text(code));
}

// The MP4's bytes go to the OutputFile's descriptor through a custom AVIOContext (libavformat
// never opens the file by name for writing, so it never has a name until finish()).
int write_to_fd(void* opaque, uint8_t* data, int size) {
  const int fd = *static_cast<int*>(opaque);
  if (!write_all(fd, data, static_cast<std::size_t>(size))) return AVERROR(errno);
  return size;
}

int64_t seek_fd(void* opaque, int64_t offset, int whence) {
  const int fd = *static_cast<int*>(opaque);
  if (whence == AVSEEK_SIZE) {
    struct stat st {};
    return ::fstat(fd, &st) == 0 ? static_cast<int64_t>(st.st_size) : AVERROR(errno);
  }
  const off_t at = ::lseek(fd, static_cast<off_t>(offset), whence & ~AVSEEK_FORCE);
  return at < 0 ? AVERROR(errno) : static_cast<int64_t>(at);
}

}  // namespace

const std::vector<std::string>& x264_presets() {
  static const std::vector<std::string> names = {"ultrafast", "superfast", "veryfast", "faster",
                                                 "fast",      "medium",    "slow",     "slower",
                                                 "veryslow",  "placebo"};
  return names;
}

bool is_x264_preset(std::string_view name) {
  const auto& names = x264_presets();
  return std::find(names.begin(), names.end(), name) != names.end();
}

void validate_video_options(const VideoWriterOptions& options) {
  if (!std::isfinite(options.fps) || options.fps < kMinFps || options.fps > 1000.0) {
    char text[96];
    std::snprintf(text, sizeof text, "fps must be in [%g, 1000] (frames per second), got %g", kMinFps, options.fps);
    throw std::invalid_argument(text);
  }
  if (options.crf < 0 || options.crf > 51)
    throw std::invalid_argument("crf must be in 0..51, got " + std::to_string(options.crf));
  if (!is_x264_preset(options.preset)) {
    std::string list;
    for (const auto& n : x264_presets()) list += (list.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown x264 preset '" + options.preset + "' (expected one of " +
                                list + ")");
  }
}

int even_size(int n) { return n + (n & 1); }

struct VideoWriter::Impl {
  std::string path;
  std::unique_ptr<OutputFile> file;  // nameless until finish()
  int fd = -1;                       // file's descriptor, the AVIOContext's opaque
  AVIOContext* io = nullptr;
  int width = 0, height = 0;          // of the input images
  int enc_width = 0, enc_height = 0;  // even
  int frames = 0;
  bool finished = false;
  std::function<bool()> stop;  // stop_when()

  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;     // yuv420p, reused for every picture
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;
  std::vector<std::uint8_t> padded;  // RGBA of enc_width x enc_height, only for odd sizes

  ~Impl() { release(); }

  void release() {
    if (sws) sws_freeContext(sws);
    sws = nullptr;
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format) {
      avformat_free_context(format);  // AVFMT_FLAG_CUSTOM_IO: leaves io to us
      format = nullptr;
    }
    if (io) {
      av_freep(&io->buffer);
      avio_context_free(&io);
    }
  }

  void open(const VideoWriterOptions& options) {
    install_log_capture();
    take_log_error();  // forget messages that belong to someone else
    try {
      validate_video_options(options);
    } catch (const std::invalid_argument& e) {
      fail(path, e.what());
    }
    if (width <= 0 || height <= 0)
      fail(path, "bad frame size " + std::to_string(width) + "x" + std::to_string(height));
    open_container();
    open_encoder(options);
    open_muxer();
    open_frames();
  }

  // The nameless file and the container its extension names.
  void open_container() {
    try {
      file = std::make_unique<OutputFile>(path);
    } catch (const OutputFileError& e) {
      throw VideoError(e.what());
    }
    fd = file->fd();
    // Container from the target's extension. The context's url is a name the nameless file
    // can be reopened by: +faststart reads the file back to move its index to the front.
    const AVOutputFormat* container = av_guess_format(nullptr, path.c_str(), nullptr);
    if (!container || container->video_codec == AV_CODEC_ID_NONE)
      container = av_guess_format("mp4", nullptr, nullptr);
    const int ret = avformat_alloc_output_context2(&format, container, nullptr, file->reopen_path().c_str());
    if (ret < 0) fail(path, "cannot set up the container", ret);
  }

  // libx264 at the options' rate, preset and quality, tagged BT.709 limited range.
  void open_encoder(const VideoWriterOptions& options) {
    int ret = 0;

    const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
    if (!encoder) fail(path, "this FFmpeg has no libx264 encoder");
    stream = avformat_new_stream(format, nullptr);
    codec = avcodec_alloc_context3(encoder);
    if (!stream || !codec) fail(path, "out of memory setting up the encoder");

    // An exact rational rate: 30 -> 30/1, 29.97 -> 2997/100; the time base is its
    // inverse, so frame k has pts k exactly.
    const AVRational rate = av_d2q(options.fps, 100000);
    codec->codec_id = AV_CODEC_ID_H264;
    codec->width = enc_width;
    codec->height = enc_height;
    codec->pix_fmt = AV_PIX_FMT_YUV420P;
    codec->time_base = av_inv_q(rate);
    codec->framerate = rate;
    codec->color_range = AVCOL_RANGE_MPEG;
    codec->colorspace = AVCOL_SPC_BT709;
    codec->color_primaries = AVCOL_PRI_BT709;
    codec->color_trc = AVCOL_TRC_BT709;
    codec->thread_count = 0;  // x264 picks (frame threads over the machine's cores)
    if (format->oformat->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

    AVDictionary* codec_opts = nullptr;
    av_dict_set(&codec_opts, "preset", options.preset.c_str(), 0);
    av_dict_set(&codec_opts, "crf", std::to_string(options.crf).c_str(), 0);
    {
      StderrCapture x264_log;
      ret = avcodec_open2(codec, encoder, &codec_opts);
      av_dict_free(&codec_opts);
      if (ret < 0) {
        keep_log_error(x264_log.last_line());
        fail(path, "cannot open the H.264 encoder", ret);
      }
    }

    stream->time_base = codec->time_base;  // a hint: the muxer may pick a finer one
    stream->avg_frame_rate = rate;
    ret = avcodec_parameters_from_context(stream->codecpar, codec);
    if (ret < 0) fail(path, "cannot copy encoder parameters", ret);
  }

  // Our AVIOContext on the file's descriptor, and the container's header.
  void open_muxer() {

    constexpr int kIoBuffer = 1 << 16;
    auto* buffer = static_cast<unsigned char*>(av_malloc(kIoBuffer));
    if (!buffer) fail(path, "out of memory");
    // A stream (pipe, device, stdout) is written forward only: no seek, no read-back.
    io = avio_alloc_context(buffer, kIoBuffer, /*write_flag=*/1, &fd, nullptr, write_to_fd,
                            file->streaming() ? nullptr : seek_fd);
    if (!io) {
      av_free(buffer);
      fail(path, "out of memory");
    }
    format->pb = io;
    format->flags |= AVFMT_FLAG_CUSTOM_IO;
    AVDictionary* mux_opts = nullptr;
    if (file->streaming()) io->seekable = 0;
    if (std::strcmp(format->oformat->name, "mp4") == 0 || std::strcmp(format->oformat->name, "mov") == 0)
      av_dict_set(&mux_opts, "movflags", file->streaming() ? "+frag_keyframe+empty_moov+default_base_moof" : "+faststart", 0);
    const int ret = avformat_write_header(format, &mux_opts);
    av_dict_free(&mux_opts);
    if (ret < 0) fail(path, "cannot write the container header", ret);
  }

  // The reused yuv420p frame and the RGBA -> YUV converter.
  void open_frames() {

    frame = av_frame_alloc();
    packet = av_packet_alloc();
    if (!frame || !packet) fail(path, "out of memory");
    frame->format = AV_PIX_FMT_YUV420P;
    frame->width = enc_width;
    frame->height = enc_height;
    frame->color_range = AVCOL_RANGE_MPEG;
    frame->colorspace = AVCOL_SPC_BT709;
    frame->color_primaries = AVCOL_PRI_BT709;
    frame->color_trc = AVCOL_TRC_BT709;
    const int ret = av_frame_get_buffer(frame, 0);
    if (ret < 0) fail(path, "cannot allocate a frame", ret);

    // Same size in and out: swscale only converts. Full-range RGB in, BT.709 limited-range
    // YUV out, matching the tags above (swscale's default matrix is BT.601).
    sws = sws_getContext(enc_width, enc_height, AV_PIX_FMT_RGBA, enc_width, enc_height,
                         AV_PIX_FMT_YUV420P, SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr,
                         nullptr);
    if (!sws) fail(path, "cannot set up the RGBA -> YUV conversion");
    const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(sws, bt709, /*srcRange full*/ 1, bt709, /*dstRange limited*/ 0, 0,
                             1 << 16, 1 << 16);
    if (enc_width != width || enc_height != height)
      padded.resize(static_cast<std::size_t>(enc_width) * enc_height * 4);
  }

  // Odd sizes: copy into the even buffer, repeating the last column and row, so the
  // padding continues the picture instead of adding a dark line at the edge.
  const std::uint8_t* pad(const Image& image) {
    const std::size_t in_row = static_cast<std::size_t>(width) * 4;
    const std::size_t out_row = static_cast<std::size_t>(enc_width) * 4;
    for (int y = 0; y < enc_height; ++y) {
      const std::uint8_t* src = image.rgba.data() + std::min(y, height - 1) * in_row;
      std::uint8_t* dst = padded.data() + y * out_row;
      std::memcpy(dst, src, in_row);
      if (enc_width != width) std::memcpy(dst + in_row, src + in_row - 4, 4);
    }
    return padded.data();
  }

  // Sends one picture (or nullptr to flush) and writes every packet the encoder has ready.
  void encode(AVFrame* picture) {
    int ret = avcodec_send_frame(codec, picture);
    if (ret < 0) fail(path, "encoder refused a frame", ret);
    for (;;) {
      if (!picture && stop && stop()) fail(path, "stopped");  // draining: abandon, do not wait
      ret = avcodec_receive_packet(codec, packet);
      if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) return;
      if (ret < 0) fail(path, "encoding failed", ret);
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      ret = av_interleaved_write_frame(format, packet);  // takes the packet's reference
      if (ret < 0) fail_write(path, ret);
    }
  }
};

VideoWriter::VideoWriter(const std::string& path, int width, int height,
                         const VideoWriterOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->width = width;
  impl_->height = height;
  impl_->enc_width = even_size(width);
  impl_->enc_height = even_size(height);
  try {
    impl_->open(options);
  } catch (...) {
    impl_->release();
    impl_->file.reset();  // dropped, nameless
    throw;
  }
}

VideoWriter::~VideoWriter() {
  if (!impl_->finished) {
    impl_->release();
    impl_->file.reset();
  }
}

void VideoWriter::write(const Image& image) {
  Impl& w = *impl_;
  if (w.finished) fail(w.path, "write after finish");
  if (image.width != w.width || image.height != w.height)
    fail(w.path, "frame " + std::to_string(w.frames) + " is " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + ", expected " + std::to_string(w.width) + "x" +
                     std::to_string(w.height));
  // The encoder may still hold a reference to the previous picture's buffers.
  int ret = av_frame_make_writable(w.frame);
  if (ret < 0) fail(w.path, "cannot reuse the frame buffer", ret);
  const std::uint8_t* rgba = w.padded.empty() ? image.rgba.data() : w.pad(image);
  const std::uint8_t* src[1] = {rgba};
  const int src_stride[1] = {w.enc_width * 4};
  sws_scale(w.sws, src, src_stride, 0, w.enc_height, w.frame->data, w.frame->linesize);
  w.frame->pts = w.frames;
  w.encode(w.frame);
  ++w.frames;
}

void VideoWriter::finish() {
  Impl& w = *impl_;
  if (w.finished) return;
  w.encode(nullptr);  // drain x264's look-ahead
  int ret = av_write_trailer(w.format);  // +faststart rewrites the file here
  if (ret < 0) fail_write(w.path, ret);
  avio_flush(w.io);
  if (w.io->error < 0) fail_write(w.path, w.io->error);
  w.release();
  try {
    w.file->commit();
  } catch (const OutputFileError& e) {
    throw VideoError(e.what());
  }
  w.finished = true;
}

void VideoWriter::stop_when(std::function<bool()> stop) { impl_->stop = std::move(stop); }

int VideoWriter::frames_written() const { return impl_->frames; }
int VideoWriter::width() const { return impl_->width; }
int VideoWriter::height() const { return impl_->height; }
int VideoWriter::encoded_width() const { return impl_->enc_width; }
int VideoWriter::encoded_height() const { return impl_->enc_height; }
const std::string& VideoWriter::path() const { return impl_->path; }

}  // namespace clothsim
