// Reading MP4s back in the output tests (mp4_writer_test.cpp, mp4_resume_test.cpp): decoded
// with libavformat/libavcodec as an independent reader would, frame counts of files a kill
// may have torn, what ffprobe/ffmpeg say when they are installed, and the decoder's own
// error messages (what `ffmpeg -v error` prints).
#pragma once
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <string>
#include <vector>

#include "render/image/image.hpp"
#include "tests/render/output_test_support.hpp"

namespace grainflow::render::test {

namespace fs = std::filesystem;

// What an independent reader sees in the file: decoded with libavformat/libavcodec and
// converted back to RGB with the BT.709 limited-range matrix the file is tagged with.
struct Decoded {
  int width = 0, height = 0;
  double duration_s = 0.0;  // container duration
  double start_s = 0.0;     // the stream's first presentation time
  std::int64_t nb_frames_field = 0;
  AVColorSpace colorspace = AVCOL_SPC_UNSPECIFIED;
  AVColorPrimaries primaries = AVCOL_PRI_UNSPECIFIED;
  AVColorTransferCharacteristic trc = AVCOL_TRC_UNSPECIFIED;
  AVColorRange range = AVCOL_RANGE_UNSPECIFIED;
  AVPixelFormat pix_fmt = AV_PIX_FMT_NONE;
  std::string codec;
  std::vector<Image> frames;
};

inline Decoded decode(const fs::path& path) {
  Decoded d;
  AVFormatContext* fmt = nullptr;
  EXPECT_EQ(avformat_open_input(&fmt, path.c_str(), nullptr, nullptr), 0);
  if (!fmt) return d;
  EXPECT_GE(avformat_find_stream_info(fmt, nullptr), 0);
  const int si = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  EXPECT_GE(si, 0);
  const AVStream* st = fmt->streams[si];
  const AVCodecParameters* par = st->codecpar;
  d.width = par->width;
  d.height = par->height;
  d.duration_s = double(fmt->duration) / AV_TIME_BASE;
  d.start_s = st->start_time == AV_NOPTS_VALUE ? -1.0 : double(st->start_time) * av_q2d(st->time_base);
  d.nb_frames_field = st->nb_frames;
  d.colorspace = par->color_space;
  d.primaries = par->color_primaries;
  d.trc = par->color_trc;
  d.range = par->color_range;
  d.pix_fmt = AVPixelFormat(par->format);
  d.codec = avcodec_get_name(par->codec_id);

  const AVCodec* dec = avcodec_find_decoder(par->codec_id);
  AVCodecContext* ctx = avcodec_alloc_context3(dec);
  avcodec_parameters_to_context(ctx, par);
  ctx->thread_count = 1;
  EXPECT_EQ(avcodec_open2(ctx, dec, nullptr), 0);
  AVPacket* pkt = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* sws = nullptr;
  auto take = [&] {
    while (avcodec_receive_frame(ctx, frame) == 0) {
      sws = sws_getCachedContext(sws, frame->width, frame->height, AVPixelFormat(frame->format), frame->width,
                                 frame->height, AV_PIX_FMT_RGBA, SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr,
                                 nullptr);
      const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
      sws_setColorspaceDetails(sws, bt709, 0, bt709, 1, 0, 1 << 16, 1 << 16);
      Image im(frame->width, frame->height);
      std::uint8_t* dst[1] = {im.rgba.data()};
      const int stride[1] = {im.width * 4};
      sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, stride);
      d.frames.push_back(std::move(im));
    }
  };
  while (av_read_frame(fmt, pkt) >= 0) {
    if (pkt->stream_index == si) {
      EXPECT_EQ(avcodec_send_packet(ctx, pkt), 0);
      take();
    }
    av_packet_unref(pkt);
  }
  avcodec_send_packet(ctx, nullptr);
  take();
  sws_freeContext(sws);
  av_frame_free(&frame);
  av_packet_free(&pkt);
  avcodec_free_context(&ctx);
  avformat_close_input(&fmt);
  return d;
}

// PSNR over R, G, B of `a` against the top-left a.width x a.height of `b`.
inline double psnr_rgb(const Image& a, const Image& b) {
  double se = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double e = double(a.pixel(x, y)[c]) - double(b.pixel(x, y)[c]);
        se += e * e;
      }
  const double mse = se / (3.0 * a.width * a.height);
  return 10.0 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
}

// Frames a player gets out of a file that may end in a torn fragment: decoding stops at
// the first error instead of failing the test, as a player stops at the end.
inline std::int64_t decodable_frames(const fs::path& path) {
  // A torn fragment makes the decoder complain; that is expected here, not news.
  struct Quiet {
    int level = av_log_get_level();
    Quiet() { av_log_set_level(AV_LOG_FATAL); }
    ~Quiet() { av_log_set_level(level); }
  } quiet;
  AVFormatContext* fmt = nullptr;
  if (avformat_open_input(&fmt, path.c_str(), nullptr, nullptr) != 0) return -1;
  std::int64_t n = 0;
  const int si = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (si >= 0) {
    const AVCodecParameters* par = fmt->streams[si]->codecpar;
    const AVCodec* dec = avcodec_find_decoder(par->codec_id);
    AVCodecContext* ctx = avcodec_alloc_context3(dec);
    avcodec_parameters_to_context(ctx, par);
    ctx->thread_count = 1;
    AVPacket* pkt = av_packet_alloc();
    AVFrame* frame = av_frame_alloc();
    if (avcodec_open2(ctx, dec, nullptr) == 0) {
      while (av_read_frame(fmt, pkt) >= 0) {
        if (pkt->stream_index == si && avcodec_send_packet(ctx, pkt) == 0)
          while (avcodec_receive_frame(ctx, frame) == 0) ++n;
        av_packet_unref(pkt);
      }
      avcodec_send_packet(ctx, nullptr);
      while (avcodec_receive_frame(ctx, frame) == 0) ++n;
    }
    av_frame_free(&frame);
    av_packet_free(&pkt);
    avcodec_free_context(&ctx);
  }
  avformat_close_input(&fmt);
  return n;
}

// What a user's `ffprobe` says, when it is installed (empty otherwise).
inline std::string ffprobe(const std::string& args, const fs::path& path) {
  if (std::system("command -v ffprobe >/dev/null 2>&1") != 0) return {};
  const std::string cmd = "ffprobe -v error " + args + " '" + path.string() + "' 2>&1";
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}


// What `ffmpeg -v error -i FILE -f null -` prints (decoding every frame, errors only), or
// "not installed". Empty: a clean decode.
inline std::string ffmpeg_decode_errors(const fs::path& path) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) return "not installed";
  const std::string cmd = "ffmpeg -nostdin -v error -i '" + path.string() + "' -f null - 2>&1";
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    if (pclose(p) != 0 && out.empty()) out = "ffmpeg failed";
  }
  return out;
}

inline bool ffmpeg_installed() { return std::system("command -v ffmpeg >/dev/null 2>&1") == 0; }

// Every message libavformat/libavcodec log at error level or worse while `fn` runs (the
// H.264 decoder reports damaged slices this way and conceals them; it does not fail).
template <class Fn>
std::string av_errors_during(Fn&& fn) {
  static std::mutex m;
  static std::string* sink = nullptr;
  std::string log;
  {
    std::lock_guard l(m);
    sink = &log;
  }
  av_log_set_callback([](void* avcl, int level, const char* fmt, va_list vl) {
    if (level > AV_LOG_ERROR) return;
    char line[1024];
    int print_prefix = 1;
    av_log_format_line(avcl, level, fmt, vl, line, sizeof line, &print_prefix);
    std::lock_guard l(m);
    if (sink) *sink += line;
  });
  fn();
  av_log_set_callback(av_log_default_callback);
  std::lock_guard l(m);
  sink = nullptr;
  return log;
}

}  // namespace grainflow::render::test
