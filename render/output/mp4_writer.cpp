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
#include <cerrno>
#include <cstring>
#include <optional>
#include <utility>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {

std::string av_reason(int err) {
  // Spelled the way users search for it; av_strerror capitalises it mid-sentence.
  if (err == AVERROR(ENOSPC)) return "no space left on device";
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
  std::filesystem::path path;     // the finished video
  std::filesystem::path partial;  // the fragmented video while encoding: path + ".partial"
  int width = 0, height = 0;          // frame size given by the caller
  int enc_width = 0, enc_height = 0;  // padded to even
  Mp4Options options;

  AVFormatContext* format = nullptr;  // the fragmented muxer writing `partial`
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;
  Image padded;  // only for odd sizes: the frame with its last column/row repeated
  std::int64_t frames = 0;   // sent to the encoder
  std::int64_t packets = 0;  // given to the muxer
  std::int64_t on_disk = 0;  // in fragments the kernel holds: they survive SIGKILL
  bool partial_created = false;
  bool opened = false;          // open() completed: the encoder and muxer are usable
  bool finished = false;        // finish() was called, whatever its outcome
  bool published = false;       // `path` holds the finished video
  std::string error;            // the first encoder/IO error, reported again by later calls

  ~Impl();

  std::string where() const { return "MP4 '" + path.string() + "'"; }
  // Records the first error and throws it; a failure caused by an earlier one (a muxer
  // whose file already failed, say) reports the earlier, which names the cause.
  [[noreturn]] void fail(const std::string& what) {
    if (error.empty()) error = where() + ": " + what;
    throw Error(error);
  }
  [[noreturn]] void fail(const std::string& what, int err) { fail(what + ": " + av_reason(err)); }
  // A write to the .partial failed (a full disk, most often): say what is left of it.
  [[noreturn]] void fail_write(int err) {
    fail("cannot write '" + partial.string() + "': " + av_reason(err) +
         (on_disk > 0 ? "; its first " + std::to_string(on_disk) + " frames remain playable there"
                      : "; no frame reached it, so it is removed"));
  }
  void throw_if_failed() const {
    if (!error.empty()) throw Error(error);
  }

  void open();
  void drain(bool flushing);
  void close_partial();
  void publish();
};

Mp4Writer::Impl::~Impl() {
  // Destroyed unfinished: the run stopped for a reason elsewhere (an exception in the
  // simulation, a failing sibling sink). The frames given so far are computed work, so the
  // ones still in the encoder are flushed and the .partial is closed complete.
  if (opened && format->pb && !finished && error.empty()) {
    try {
      close_partial();
    } catch (...) {
      // Recorded in `error`; a destructor reports nothing. The fragments on disk stay.
    }
  }
  sws_freeContext(sws);
  av_packet_free(&packet);
  av_frame_free(&frame);
  avcodec_free_context(&codec);
  if (format) {
    if (format->pb) avio_closep(&format->pb);
    avformat_free_context(format);
  }
  // A .partial without a single complete fragment holds no video: not worth a user's look.
  if (partial_created && !published && on_disk == 0) {
    std::error_code ec;
    std::filesystem::remove(partial, ec);
  }
}

void Mp4Writer::Impl::open() {
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");  // checked by check_mp4_options
  // x264 prints its settings and statistics at info level; batch runs want warnings only.
  // A program that chose another level keeps it.
  if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_WARNING);

  // Found now rather than after the whole encode, when finish() renames onto it.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error(where() + ": the path names a directory, a file is needed");
  partial = path;
  partial += ".partial";

  int err = avformat_alloc_output_context2(&format, nullptr, "mp4", partial.c_str());
  if (err < 0 || !format) fail("cannot create the MP4 muxer", err);
  // No library version string and no creation time in the file: same frames, same bytes.
  format->flags |= AVFMT_FLAG_BITEXACT;

  codec = avcodec_alloc_context3(encoder);
  if (!codec) fail("out of memory allocating the encoder");
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
    fail("libx264 rejected option '" + unused + "'");
  }
  av_dict_free(&codec_opts);

  stream = avformat_new_stream(format, nullptr);
  if (!stream) fail("out of memory allocating the stream");
  stream->time_base = codec->time_base;
  stream->avg_frame_rate = codec->framerate;
  err = avcodec_parameters_from_context(stream->codecpar, codec);
  if (err < 0) fail("cannot copy the encoder parameters", err);

  // Truncates a .partial that a killed earlier run left: this run's video replaces it.
  err = avio_open(&format->pb, partial.c_str(), AVIO_FLAG_WRITE);
  if (err < 0) fail("cannot create '" + partial.string() + "'", err);
  partial_created = true;

  AVDictionary* mux_opts = nullptr;
  // empty_moov: the index (codec setup, no samples) goes first, so the file is playable
  // from the first fragment on. frag_custom: fragments are cut where drain() says, after
  // every frame. default_base_moof: offsets relative to each fragment, the form browsers'
  // Media Source Extensions require and every demuxer reads.
  av_dict_set(&mux_opts, "movflags", "frag_custom+empty_moov+default_base_moof", 0);
  err = avformat_write_header(format, &mux_opts);
  av_dict_free(&mux_opts);
  if (err < 0) fail("cannot write the MP4 header to '" + partial.string() + "'", err);
  avio_flush(format->pb);
  if (format->pb->error < 0) fail_write(format->pb->error);

  frame = av_frame_alloc();
  packet = av_packet_alloc();
  if (!frame || !packet) fail("out of memory allocating frames");
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
  if (!sws) fail("swscale cannot convert RGBA to yuv420p");
  // Full-range RGB in, limited-range BT.709 YCbCr out — matching the tags above.
  const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
  sws_setColorspaceDetails(sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);

  if (enc_width != width || enc_height != height) padded = Image(enc_width, enc_height);
  opened = true;
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
    // Not the interleaving variant: one stream arrives in decode order already, and the
    // fragment cut below must close over exactly this packet.
    err = av_write_frame(format, packet);
    av_packet_unref(packet);
    if (err < 0) fail_write(err);
    ++packets;
    // A fragment per frame: what a kill loses is only what x264 still holds. A fragment
    // costs ~120 bytes (moof + mdat headers), nothing beside a frame's tens of kilobytes.
    err = av_write_frame(format, nullptr);
    if (err < 0) fail_write(err);
    avio_flush(format->pb);  // out of this process's buffer into the kernel's
    if (format->pb->error < 0) fail_write(format->pb->error);
    on_disk = packets;
  }
}

// Flushes the encoder's delayed frames into the .partial, writes its trailer (the
// fragment index, for seeking) and closes it.
void Mp4Writer::Impl::close_partial() {
  int err = avcodec_send_frame(codec, nullptr);
  if (err < 0) fail("cannot flush the encoder", err);
  drain(true);
  err = av_write_trailer(format);
  if (err < 0) fail_write(err);
  err = avio_closep(&format->pb);
  if (err < 0) fail_write(err);
}

// Copies the .partial's packets into a standard MP4 under `path` (see the header). The
// fragmented muxer shifted the timestamps to start decoding at 0 (it writes no edit list),
// so they are shifted back to show frame 0 at time 0, and the standard muxer writes the
// edit list for the B-frame delay, as a direct encode does.
void Mp4Writer::Impl::publish() {
  const auto kept = [&] {
    return "; the complete video (fragmented MP4, " + std::to_string(packets) + " frames) stays in '" +
           partial.string() + "'";
  };
  AVFormatContext* in = nullptr;
  AVFormatContext* out = nullptr;
  AVPacket* pkt = av_packet_alloc();
  struct Cleanup {
    AVFormatContext*& in;
    AVFormatContext*& out;
    AVPacket*& pkt;
    ~Cleanup() {
      av_packet_free(&pkt);
      avformat_close_input(&in);
      if (out) {
        if (out->pb) avio_closep(&out->pb);
        avformat_free_context(out);
      }
    }
  } cleanup{in, out, pkt};
  if (!pkt) fail("out of memory allocating a packet");

  std::optional<io::AtomicFile> file;
  try {
    file.emplace(path);
  } catch (const Error& e) {
    fail(e.what() + kept());
  }
  int err = avformat_open_input(&in, partial.c_str(), av_find_input_format("mp4"), nullptr);
  if (err < 0) fail("cannot read back '" + partial.string() + "': " + av_reason(err) + kept());
  if (in->nb_streams != 1) fail("'" + partial.string() + "' does not hold one video stream" + kept());
  const AVRational in_tb = in->streams[0]->time_base;

  const std::string tmp = file->path().string();
  err = avformat_alloc_output_context2(&out, nullptr, "mp4", tmp.c_str());
  if (err < 0 || !out) fail("cannot create the MP4 muxer: " + av_reason(err) + kept());
  out->flags |= AVFMT_FLAG_BITEXACT;
  AVStream* os = avformat_new_stream(out, nullptr);
  if (!os) fail("out of memory allocating the stream" + kept());
  os->time_base = codec->time_base;
  os->avg_frame_rate = codec->framerate;
  // The demuxer's parameters, not the encoder's: its packets come length-prefixed with an
  // avcC header, while x264's are Annex B, which the muxer would "convert" a second time.
  err = avcodec_parameters_copy(os->codecpar, in->streams[0]->codecpar);
  if (err < 0) fail("cannot copy the stream parameters: " + av_reason(err) + kept());
  os->codecpar->codec_tag = 0;  // the muxer picks avc1 itself, as for a direct encode
  err = avio_open(&out->pb, tmp.c_str(), AVIO_FLAG_WRITE);
  if (err < 0) fail("cannot open '" + tmp + "' for writing: " + av_reason(err) + kept());
  AVDictionary* mux_opts = nullptr;
  // faststart moves the index to the front once complete, so players and browsers can
  // start before downloading everything. It rewrites the temporary file in place.
  av_dict_set(&mux_opts, "movflags", "+faststart", 0);
  err = avformat_write_header(out, &mux_opts);
  av_dict_free(&mux_opts);
  if (err < 0) fail("cannot write the MP4 header to '" + tmp + "': " + av_reason(err) + kept());

  std::int64_t copied = 0, shift = 0;
  while ((err = av_read_frame(in, pkt)) >= 0) {
    av_packet_rescale_ts(pkt, in_tb, codec->time_base);
    // Frame 0 comes first in decode order; its time is the shift the fragmented muxer added.
    if (copied == 0) shift = pkt->pts;
    pkt->pts -= shift;
    pkt->dts -= shift;
    av_packet_rescale_ts(pkt, codec->time_base, os->time_base);
    pkt->stream_index = os->index;
    pkt->pos = -1;
    err = av_write_frame(out, pkt);
    av_packet_unref(pkt);
    if (err < 0) fail("cannot write '" + tmp + "': " + av_reason(err) + kept());
    ++copied;
  }
  if (err != AVERROR_EOF) fail("cannot read back '" + partial.string() + "': " + av_reason(err) + kept());
  if (copied != packets)
    fail("'" + partial.string() + "' reads back " + std::to_string(copied) + " of " + std::to_string(packets) +
         " frames" + kept());
  err = av_write_trailer(out);
  if (err < 0) fail("cannot write the MP4 index to '" + tmp + "': " + av_reason(err) + kept());
  err = avio_closep(&out->pb);
  if (err < 0) fail("cannot close '" + tmp + "': " + av_reason(err) + kept());
  try {
    file->commit();
  } catch (const Error& e) {
    fail(e.what() + kept());
  }
  published = true;
  // The finished video is in place; a .partial that cannot be removed is only clutter.
  std::error_code ec;
  std::filesystem::remove(partial, ec);
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
  m.throw_if_failed();
  if (m.finished) throw Error(m.where() + ": write() after finish()");
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
  m.throw_if_failed();
  if (m.finished) throw Error(m.where() + ": finish() called twice");
  m.finished = true;
  m.close_partial();
  m.publish();
}

std::int64_t Mp4Writer::frames_written() const { return impl_->frames; }
std::int64_t Mp4Writer::frames_on_disk() const { return impl_->on_disk; }
const std::filesystem::path& Mp4Writer::partial_path() const { return impl_->partial; }
int Mp4Writer::encoded_width() const { return impl_->enc_width; }
int Mp4Writer::encoded_height() const { return impl_->enc_height; }

}  // namespace grainflow::render
