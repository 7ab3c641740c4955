#include "render/output/mp4_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/output/mp4_sink.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::smooth_pattern;

// What an independent reader sees in the file: decoded with libavformat/libavcodec and
// converted back to RGB with the BT.709 limited-range matrix the file is tagged with.
struct Decoded {
  int width = 0, height = 0;
  double duration_s = 0.0;  // container duration
  std::int64_t nb_frames_field = 0;
  AVColorSpace colorspace = AVCOL_SPC_UNSPECIFIED;
  AVColorPrimaries primaries = AVCOL_PRI_UNSPECIFIED;
  AVColorTransferCharacteristic trc = AVCOL_TRC_UNSPECIFIED;
  AVColorRange range = AVCOL_RANGE_UNSPECIFIED;
  AVPixelFormat pix_fmt = AV_PIX_FMT_NONE;
  std::string codec;
  std::vector<Image> frames;
};

Decoded decode(const fs::path& path) {
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
double psnr_rgb(const Image& a, const Image& b) {
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

TEST(Mp4Writer, RoundTripFramesSizeDurationAndQuality) {
  const fs::path path = fresh_dir() / "clip.mp4";
  const int w = 160, h = 96, n = 45, fps = 30;
  std::vector<Image> src;
  {
    Mp4Writer writer(path, w, h, Mp4Options{fps, 20, "veryfast", 2});
    for (int k = 0; k < n; ++k) {
      src.push_back(smooth_pattern(w, h, 0.2 * k));
      writer.write(src.back());
    }
    EXPECT_FALSE(fs::exists(path)) << "the final name must not exist before finish()";
    writer.finish();
    EXPECT_EQ(writer.frames_written(), n);
  }
  ASSERT_TRUE(fs::exists(path));
  const Decoded d = decode(path);
  EXPECT_EQ(d.codec, "h264");
  EXPECT_EQ(d.width, w);
  EXPECT_EQ(d.height, h);
  EXPECT_EQ(d.pix_fmt, AV_PIX_FMT_YUV420P);
  ASSERT_EQ(int(d.frames.size()), n);
  EXPECT_EQ(d.nb_frames_field, n);
  EXPECT_NEAR(d.duration_s, double(n) / fps, 0.5 / fps) << "every frame, the last included, lasts 1/fps";
  for (int k : {0, 10, n - 1}) {
    const double p = psnr_rgb(src[k], d.frames[k]);
    EXPECT_GT(p, 35.0) << "frame " << k;
  }
  // Frames come out in order: frame 10 matches source 10 much better than source 30.
  EXPECT_GT(psnr_rgb(src[10], d.frames[10]), psnr_rgb(src[30], d.frames[10]) + 5.0);
}

TEST(Mp4Writer, TaggedBt709LimitedRangeWithIndexFirst) {
  const fs::path path = fresh_dir() / "tags.mp4";
  {
    Mp4Writer writer(path, 64, 64);
    for (int k = 0; k < 5; ++k) writer.write(smooth_pattern(64, 64, k));
    writer.finish();
  }
  const Decoded d = decode(path);
  EXPECT_EQ(d.colorspace, AVCOL_SPC_BT709);
  EXPECT_EQ(d.primaries, AVCOL_PRI_BT709);
  EXPECT_EQ(d.trc, AVCOL_TRC_BT709);
  EXPECT_EQ(d.range, AVCOL_RANGE_MPEG);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const auto moov = bytes.find("moov"), mdat = bytes.find("mdat");
  ASSERT_NE(moov, std::string::npos);
  ASSERT_NE(mdat, std::string::npos);
  EXPECT_LT(moov, mdat) << "+faststart puts the index before the media data";
}

TEST(Mp4Writer, OddSizeIsPaddedToEvenByRepeatingEdges) {
  const fs::path path = fresh_dir() / "odd.mp4";
  const int w = 161, h = 97;
  const Image src = smooth_pattern(w, h, 1.0);
  {
    Mp4Writer writer(path, w, h);
    EXPECT_EQ(writer.encoded_width(), 162);
    EXPECT_EQ(writer.encoded_height(), 98);
    for (int k = 0; k < 3; ++k) writer.write(src);
    writer.finish();
  }
  const Decoded d = decode(path);
  EXPECT_EQ(d.width, 162);
  EXPECT_EQ(d.height, 98);
  ASSERT_EQ(d.frames.size(), 3u);
  EXPECT_GT(psnr_rgb(src, d.frames[2]), 35.0);
  // The padding repeats the last column/row, so it looks like its neighbour (no black
  // seam that would bleed into the picture through chroma subsampling).
  int worst = 0;
  for (int y = 0; y < h; ++y)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(int(d.frames[2].pixel(w, y)[c]) - int(src.pixel(w - 1, y)[c])));
  for (int x = 0; x < w; ++x)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(int(d.frames[2].pixel(x, h)[c]) - int(src.pixel(x, h - 1)[c])));
  EXPECT_LE(worst, 12);
}

TEST(Mp4Writer, UnfinishedWriterLeavesNoFile) {
  const fs::path dir = fresh_dir();
  {
    Mp4Writer writer(dir / "killed.mp4", 64, 48);
    for (int k = 0; k < 10; ++k) writer.write(smooth_pattern(64, 48, k));
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "neither the final file nor the temporary may remain";
}

TEST(Mp4Writer, RejectsBadOptionsAndFrameSizeChanges) {
  const fs::path dir = fresh_dir();
  EXPECT_THROW(Mp4Writer(dir / "a.mp4", 64, 64, Mp4Options{30, 20, "turbo", 2}), Error);
  EXPECT_THROW(Mp4Writer(dir / "a.mp4", 64, 64, Mp4Options{0, 20, "fast", 2}), Error);
  EXPECT_THROW(Mp4Writer(dir / "a.mp4", 64, 64, Mp4Options{30, 52, "fast", 2}), Error);
  EXPECT_THROW(Mp4Writer(dir / "a.mp4", 0, 64), Error);
  EXPECT_THROW(Mp4Writer(dir / "nodir" / "a.mp4", 64, 64), Error);
  try {
    Mp4Options o;
    o.preset = "turbo";
    check_mp4_options(dir / "a.mp4", o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'turbo'"), std::string::npos) << e.what();
  }
  Mp4Writer writer(dir / "b.mp4", 64, 64);
  writer.write(smooth_pattern(64, 64, 0));
  EXPECT_THROW(writer.write(smooth_pattern(64, 32, 0)), Error);
  EXPECT_TRUE(fs::exists(dir / "b.mp4") == false);
}

TEST(Mp4Sink, TakesSizeFromFirstFrameAndFinishes) {
  const fs::path dir = fresh_dir();
  {
    Mp4Sink sink(dir / "run.mp4", Mp4Options{25, 23, "ultrafast", 1});
    for (int k = 0; k < 10; ++k) sink.consume(smooth_pattern(96, 54, k), k, 0.1 * k);
    EXPECT_EQ(sink.frames_written(), 10);
    sink.finish();
  }
  const Decoded d = decode(dir / "run.mp4");
  EXPECT_EQ(d.frames.size(), 10u);
  EXPECT_EQ(d.width, 96);
  EXPECT_NEAR(d.duration_s, 10.0 / 25.0, 0.5 / 25.0);
}

TEST(Mp4Sink, FinishWithoutFramesAndBadDirectoryAreErrors) {
  const fs::path dir = fresh_dir();
  EXPECT_THROW(Mp4Sink(dir / "missing" / "x.mp4"), Error);
  Mp4Sink sink(dir / "none.mp4");
  EXPECT_THROW(sink.finish(), Error);
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace grainflow::render
