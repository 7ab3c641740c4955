#include "render/output/mp4_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cstring>
#include <optional>
#include <utility>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {

std::string av_reason(int err) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
  av_strerror(err, buf, sizeof(buf));
  return buf;
}

}  // namespace

void check_mp4_options(const std::filesystem::path& path, const Mp4Options& options) {
  const auto where = [&] { return "MP4 '" + path.string() + "'"; };
  if (options.fps < 1 || options.fps > 1000)
    throw Error(where() + ": fps " + std::to_string(options.fps) + " is out of range (allowed 1..1000)");
  if (options.crf < 0 || options.crf > 51)
    throw Error(where() + ": crf " + std::to_string(options.crf) + " is out of range (allowed 0..51)");
  if (options.threads < 0 || options.threads > 64)
    throw Error(where() + ": threads " + std::to_string(options.threads) + " is out of range (allowed 0..64, 0 = auto)");
  static constexpr const char* presets[] = {"ultrafast", "superfast", "veryfast", "faster", "fast",
                                            "medium",    "slow",      "slower",   "veryslow", "placebo"};
  if (std::none_of(std::begin(presets), std::end(presets), [&](const char* p) { return options.preset == p; }))
    throw Error(where() + ": x264 preset '" + options.preset +
                "' is unknown (allowed ultrafast, superfast, veryfast, faster, fast, medium, slow, slower, "
                "veryslow, placebo)");
  if (!avcodec_find_encoder_by_name("libx264"))
    throw Error(where() + ": the H.264 encoder 'libx264' is not available in this FFmpeg build (libavcodec " +
                AV_STRINGIFY(LIBAVCODEC_VERSION) + "); install an FFmpeg built with libx264 (Debian's "
                "libavcodec59 includes it)");
}

struct Mp4Writer::Impl {
  std::filesystem::path path;
  int width = 0, height = 0;          // frame size given by the caller
  int enc_width = 0, enc_height = 0;  // padded to even
  Mp4Options options;
  std::optional<io::AtomicFile> file;

  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;
  Image padded;  // only for odd sizes: the frame with its last column/row repeated
  std::int64_t frames = 0;
  bool finished = false;

  ~Impl() {
    sws_freeContext(sws);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format) {
      if (format->pb) avio_closep(&format->pb);
      avformat_free_context(format);
    }
    // `file` (declared earlier) is destroyed after this body: it removes the temporary
    // unless finish() committed it.
  }

  [[noreturn]] void fail(const std::string& what, int err) const {
    throw Error("MP4 '" + path.string() + "': " + what + ": " + av_reason(err));
  }

  void open();
  void drain(bool flushing);
};

void Mp4Writer::Impl::open() {
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");  // checked by check_mp4_options
  // x264 prints its settings and statistics at info level; batch runs want warnings only.
  // A program that chose another level keeps it.
  if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_WARNING);

  file.emplace(path);  // throws with the OS reason if the directory is not writable

  int err = avformat_alloc_output_context2(&format, nullptr, "mp4", file->path().c_str());
  if (err < 0 || !format) fail("cannot create the MP4 muxer", err);

  codec = avcodec_alloc_context3(encoder);
  if (!codec) throw Error("MP4 '" + path.string() + "': out of memory allocating the encoder");
  codec->width = enc_width;
  codec->height = enc_height;
  codec->pix_fmt = AV_PIX_FMT_YUV420P;
  codec->time_base = AVRational{1, options.fps};
  codec->framerate = AVRational{options.fps, 1};
  codec->sample_aspect_ratio = AVRational{1, 1};
  codec->thread_count = options.threads;
  // Tag what swscale produces, so players do not guess BT.601 for HD.
  codec->color_range = AVCOL_RANGE_MPEG;
  codec->colorspace = AVCOL_SPC_BT709;
  codec->color_primaries = AVCOL_PRI_BT709;
  codec->color_trc = AVCOL_TRC_BT709;
  if (format->oformat->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

  AVDictionary* codec_opts = nullptr;
  av_dict_set(&codec_opts, "preset", options.preset.c_str(), 0);
  av_dict_set_int(&codec_opts, "crf", options.crf, 0);
  err = avcodec_open2(codec, encoder, &codec_opts);
  if (err < 0) {
    av_dict_free(&codec_opts);
    fail("cannot open libx264 (preset '" + options.preset + "', crf " + std::to_string(options.crf) + ")", err);
  }
  if (av_dict_count(codec_opts) > 0) {
    std::string unused = av_dict_get(codec_opts, "", nullptr, AV_DICT_IGNORE_SUFFIX)->key;
    av_dict_free(&codec_opts);
    throw Error("MP4 '" + path.string() + "': libx264 rejected option '" + unused + "'");
  }
  av_dict_free(&codec_opts);

  stream = avformat_new_stream(format, nullptr);
  if (!stream) throw Error("MP4 '" + path.string() + "': out of memory allocating the stream");
  stream->time_base = codec->time_base;
  stream->avg_frame_rate = codec->framerate;
  err = avcodec_parameters_from_context(stream->codecpar, codec);
  if (err < 0) fail("cannot copy the encoder parameters", err);

  err = avio_open(&format->pb, file->path().c_str(), AVIO_FLAG_WRITE);
  if (err < 0) fail("cannot open '" + file->path().string() + "' for writing", err);

  AVDictionary* mux_opts = nullptr;
  // faststart moves the index to the front once complete, so players and browsers can
  // start before downloading everything. It rewrites the temporary file in place.
  av_dict_set(&mux_opts, "movflags", "+faststart", 0);
  err = avformat_write_header(format, &mux_opts);
  av_dict_free(&mux_opts);
  if (err < 0) fail("cannot write the MP4 header", err);

  frame = av_frame_alloc();
  packet = av_packet_alloc();
  if (!frame || !packet) throw Error("MP4 '" + path.string() + "': out of memory allocating frames");
  frame->format = AV_PIX_FMT_YUV420P;
  frame->width = enc_width;
  frame->height = enc_height;
  frame->color_range = AVCOL_RANGE_MPEG;
  frame->colorspace = AVCOL_SPC_BT709;
  frame->color_primaries = AVCOL_PRI_BT709;
  frame->color_trc = AVCOL_TRC_BT709;
  err = av_frame_get_buffer(frame, 0);
  if (err < 0) fail("cannot allocate a video frame", err);

  sws = sws_getContext(enc_width, enc_height, AV_PIX_FMT_RGBA, enc_width, enc_height, AV_PIX_FMT_YUV420P,
                       SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr, nullptr);
  if (!sws) throw Error("MP4 '" + path.string() + "': swscale cannot convert RGBA to yuv420p");
  // Full-range RGB in, limited-range BT.709 YCbCr out — matching the tags above.
  const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
  sws_setColorspaceDetails(sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);

  if (enc_width != width || enc_height != height) padded = Image(enc_width, enc_height);
}

void Mp4Writer::Impl::drain(bool flushing) {
  for (;;) {
    int err = avcodec_receive_packet(codec, packet);
    if (err == AVERROR(EAGAIN) && !flushing) return;
    if (err == AVERROR_EOF) return;
    if (err < 0) fail("encoding failed", err);
    // Every frame lasts one frame period; x264 does not set it, and without it the last
    // frame would have no duration in the file.
    if (packet->duration == 0) packet->duration = 1;
    av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
    packet->stream_index = stream->index;
    err = av_interleaved_write_frame(format, packet);  // takes ownership of the payload
    if (err < 0) fail("cannot write a packet", err);
  }
}

Mp4Writer::Mp4Writer(std::filesystem::path path, int width, int height, Mp4Options options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = std::move(path);
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error("MP4 '" + m.path.string() + "'" + ": frame size " + std::to_string(width) + "x" + std::to_string(height) +
                " is out of range (allowed 1..16384 per side)");
  check_mp4_options(m.path, options);
  m.width = width;
  m.height = height;
  m.enc_width = width + (width & 1);
  m.enc_height = height + (height & 1);
  m.options = std::move(options);
  m.open();
}

Mp4Writer::~Mp4Writer() = default;

void Mp4Writer::write(const Image& image) {
  Impl& m = *impl_;
  if (m.finished) throw Error("MP4 '" + m.path.string() + "': write() after finish()");
  if (image.width != m.width || image.height != m.height)
    throw Error("MP4 '" + m.path.string() + "': frame " + std::to_string(m.frames) + " is " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + " but the video is " +
                std::to_string(m.width) + "x" + std::to_string(m.height) + " (all frames must have one size)");

  const std::uint8_t* src = image.rgba.data();
  if (!m.padded.empty()) {
    const std::size_t row = static_cast<std::size_t>(m.width) * 4;
    for (int y = 0; y < m.enc_height; ++y) {
      const std::uint8_t* s = image.pixel(0, std::min(y, m.height - 1));
      std::uint8_t* d = m.padded.pixel(0, y);
      std::memcpy(d, s, row);
      if (m.enc_width != m.width) std::memcpy(d + row, s + row - 4, 4);
    }
    src = m.padded.rgba.data();
  }

  // The encoder may still reference the previous frame's buffer (lookahead threads).
  int err = av_frame_make_writable(m.frame);
  if (err < 0) m.fail("cannot get a writable frame", err);
  const std::uint8_t* src_planes[1] = {src};
  const int src_strides[1] = {m.enc_width * 4};
  sws_scale(m.sws, src_planes, src_strides, 0, m.enc_height, m.frame->data, m.frame->linesize);
  m.frame->pts = m.frames;

  err = avcodec_send_frame(m.codec, m.frame);
  if (err < 0) m.fail("cannot send frame " + std::to_string(m.frames) + " to the encoder", err);
  ++m.frames;
  m.drain(false);
}

void Mp4Writer::finish() {
  Impl& m = *impl_;
  if (m.finished) throw Error("MP4 '" + m.path.string() + "': finish() called twice");
  m.finished = true;
  int err = avcodec_send_frame(m.codec, nullptr);
  if (err < 0) m.fail("cannot flush the encoder", err);
  m.drain(true);
  err = av_write_trailer(m.format);
  if (err < 0) m.fail("cannot write the MP4 index", err);
  err = avio_closep(&m.format->pb);
  if (err < 0) m.fail("cannot close the file", err);
  m.file->commit();
}

std::int64_t Mp4Writer::frames_written() const { return impl_->frames; }
int Mp4Writer::encoded_width() const { return impl_->enc_width; }
int Mp4Writer::encoded_height() const { return impl_->enc_height; }

}  // namespace grainflow::render
