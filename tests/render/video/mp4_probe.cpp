#include "render/video/mp4_probe.h"

#include <array>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

namespace clothsim::test {

namespace {

void check(int ret, const std::string& what) {
  if (ret < 0) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(ret, buf, sizeof buf);
    throw std::runtime_error(what + ": " + buf);
  }
}

std::string or_empty(const char* s) { return s ? s : ""; }

// Top-level boxes of an ISO media file, in order: +faststart puts moov before mdat.
bool moov_before_mdat(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t at = 0;
  while (at + 8 <= bytes.size()) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at);
    std::uint64_t size = (std::uint64_t(p[0]) << 24) | (p[1] << 16) | (p[2] << 8) | p[3];
    const std::string type = bytes.substr(at + 4, 4);
    if (type == "moov") return true;
    if (type == "mdat") return false;
    if (size == 1 && at + 16 <= bytes.size()) {
      size = 0;
      for (int i = 8; i < 16; ++i) size = (size << 8) | p[i];
    }
    if (size < 8) return false;
    at += size;
  }
  return false;
}

}  // namespace

Mp4Info probe_mp4(const std::string& path, bool decode_pictures) {
  AVFormatContext* fmt = nullptr;
  check(avformat_open_input(&fmt, path.c_str(), nullptr, nullptr), "open " + path);
  std::unique_ptr<AVFormatContext, void (*)(AVFormatContext*)> fmt_guard(
      fmt, [](AVFormatContext* f) { avformat_close_input(&f); });
  check(avformat_find_stream_info(fmt, nullptr), "stream info");
  const int index = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  check(index, "video stream");
  const AVStream* stream = fmt->streams[index];
  const AVCodecParameters* par = stream->codecpar;

  Mp4Info info;
  info.codec = avcodec_get_name(par->codec_id);
  info.pixel_format = or_empty(av_get_pix_fmt_name(static_cast<AVPixelFormat>(par->format)));
  info.width = par->width;
  info.height = par->height;
  info.rate_num = stream->avg_frame_rate.num;
  info.rate_den = stream->avg_frame_rate.den;
  info.color_space = or_empty(av_color_space_name(par->color_space));
  info.color_primaries = or_empty(av_color_primaries_name(par->color_primaries));
  info.color_transfer = or_empty(av_color_transfer_name(par->color_trc));
  info.color_range = or_empty(av_color_range_name(par->color_range));
  info.index_first = moov_before_mdat(path);

  const AVCodec* decoder = avcodec_find_decoder(par->codec_id);
  if (!decoder) throw std::runtime_error("no decoder for " + info.codec);
  AVCodecContext* dec = avcodec_alloc_context3(decoder);
  std::unique_ptr<AVCodecContext, void (*)(AVCodecContext*)> dec_guard(
      dec, [](AVCodecContext* c) { avcodec_free_context(&c); });
  check(avcodec_parameters_to_context(dec, par), "decoder parameters");
  check(avcodec_open2(dec, decoder, nullptr), "open decoder");

  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* sws = nullptr;
  auto take_frames = [&] {
    for (;;) {
      const int ret = avcodec_receive_frame(dec, frame);
      if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) return;
      check(ret, "decode");
      Image rgba(frame->width, frame->height);
      if (decode_pictures) {
        // Back to full-range RGB with the matrix the stream is tagged with (BT.709).
        sws = sws_getCachedContext(sws, frame->width, frame->height,
                                   static_cast<AVPixelFormat>(frame->format), frame->width,
                                   frame->height, AV_PIX_FMT_RGBA, SWS_BILINEAR | SWS_ACCURATE_RND,
                                   nullptr, nullptr, nullptr);
        const int* m = sws_getCoefficients(frame->colorspace == AVCOL_SPC_BT709 ? SWS_CS_ITU709
                                                                               : SWS_CS_DEFAULT);
        sws_setColorspaceDetails(sws, m, frame->color_range == AVCOL_RANGE_JPEG, m, 1, 0, 1 << 16,
                                 1 << 16);
        std::uint8_t* dst[1] = {rgba.rgba.data()};
        const int stride[1] = {rgba.width * 4};
        sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, stride);
      }
      info.frames.push_back(std::move(rgba));
    }
  };
  try {
    while (av_read_frame(fmt, packet) >= 0) {
      if (packet->stream_index == index) check(avcodec_send_packet(dec, packet), "send packet");
      av_packet_unref(packet);
      take_frames();
    }
    check(avcodec_send_packet(dec, nullptr), "flush");
    take_frames();
  } catch (...) {
    sws_freeContext(sws);
    av_frame_free(&frame);
    av_packet_free(&packet);
    throw;
  }
  sws_freeContext(sws);
  av_frame_free(&frame);
  av_packet_free(&packet);
  return info;
}

std::array<double, 3> mean_rgb(const Image& image, int x, int y, int r) {
  std::array<double, 3> sum{0, 0, 0};
  int n = 0;
  for (int yy = y - r; yy <= y + r; ++yy)
    for (int xx = x - r; xx <= x + r; ++xx) {
      if (xx < 0 || yy < 0 || xx >= image.width || yy >= image.height) continue;
      const auto* p = image.pixel(xx, yy);
      for (int c = 0; c < 3; ++c) sum[c] += p[c];
      ++n;
    }
  for (auto& s : sum) s /= std::max(n, 1);
  return sum;
}

}  // namespace clothsim::test
