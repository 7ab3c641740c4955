#include "render/output/mp4_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

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

// The SPS and PPS NAL units of H.264 codec extradata, in either form a muxer or demuxer
// holds it: Annex B (start codes; what x264 gives) or avcC (what an MP4 stores). Emulation
// prevention bytes are kept, so the same parameter sets compare equal in both forms.
struct ParameterSets {
  std::vector<std::string> sps, pps;
  bool operator==(const ParameterSets&) const = default;
};

void add_nal(ParameterSets& ps, const std::uint8_t* p, std::size_t n) {
  if (n == 0) return;
  const int type = p[0] & 0x1f;
  if (type == 7) ps.sps.emplace_back(reinterpret_cast<const char*>(p), n);
  if (type == 8) ps.pps.emplace_back(reinterpret_cast<const char*>(p), n);
}

// nullopt: malformed avcC.
std::optional<ParameterSets> parameter_sets(const std::uint8_t* data, int size) {
  ParameterSets ps;
  if (!data || size <= 0) return ps;
  const std::size_t n = std::size_t(size);
  if (data[0] == 1) {  // avcC: version 1, profile, compatibility, level, length size, SPS, PPS
    if (n < 7) return std::nullopt;
    std::size_t at = 5;
    for (int list = 0; list < 2; ++list) {
      if (at >= n) return std::nullopt;
      const int count = list == 0 ? data[at] & 0x1f : data[at];
      ++at;
      for (int i = 0; i < count; ++i) {
        if (at + 2 > n) return std::nullopt;
        const std::size_t len = std::size_t(data[at]) << 8 | data[at + 1];
        at += 2;
        if (at + len > n) return std::nullopt;
        add_nal(ps, data + at, len);
        at += len;
      }
    }
    return ps;  // High-profile fields after the PPS (chroma format, bit depth) are in the SPS too
  }
  // Annex B: NAL units between 00 00 01 start codes (a 4-byte start code's extra 00 is the
  // previous unit's trailing zero byte, which is not part of it).
  std::size_t start = std::string::npos;
  for (std::size_t i = 0; i + 3 <= n; ++i)
    if (data[i] == 0 && data[i + 1] == 0 && data[i + 2] == 1) {
      if (start != std::string::npos) {
        std::size_t end = i;
        while (end > start && data[end - 1] == 0) --end;
        add_nal(ps, data + start, end - start);
      }
      start = i + 3;
      i += 2;
    }
  if (start != std::string::npos) add_nal(ps, data + start, n - start);
  return ps;
}

// The bytes of `file` that hold complete top-level MP4 boxes, up to the last one that is
// not a fragment header (moof) without its media data: a run killed mid-write leaves a torn
// last box, and libavformat's MP4 demuxer, which reads every fragment header when it opens
// a file, refuses the whole file over a torn one. 0 if the file cannot be read.
std::int64_t complete_boxes(std::FILE* f, std::int64_t file_size) {
  std::int64_t at = 0, good = 0;
  while (at + 8 <= file_size) {
    std::uint8_t h[16];
    if (std::fseek(f, long(at), SEEK_SET) != 0 || std::fread(h, 1, 8, f) != 8) break;
    std::uint64_t size = std::uint64_t(h[0]) << 24 | std::uint64_t(h[1]) << 16 | std::uint64_t(h[2]) << 8 | h[3];
    if (size == 1) {  // 64-bit size after the type
      if (at + 16 > file_size || std::fread(h + 8, 1, 8, f) != 8) break;
      size = 0;
      for (int i = 8; i < 16; ++i) size = size << 8 | h[i];
    } else if (size == 0) {
      size = std::uint64_t(file_size - at);  // "to the end of the file"
    }
    if (size < 8 || size > std::uint64_t(file_size - at)) break;  // torn
    at += std::int64_t(size);
    if (std::memcmp(h + 4, "moof", 4) != 0) good = at;
  }
  return good;
}

// A read-only view of the first `size` bytes of a file, for libavformat.
struct FileView {
  std::FILE* f = nullptr;
  std::int64_t size = 0, pos = 0;
  static int read(void* opaque, std::uint8_t* buf, int n) {
    auto* v = static_cast<FileView*>(opaque);
    const std::int64_t left = v->size - v->pos;
    if (left <= 0) return AVERROR_EOF;
    if (n > left) n = int(left);
    if (std::fseek(v->f, long(v->pos), SEEK_SET) != 0) return AVERROR(errno);
    const std::size_t got = std::fread(buf, 1, std::size_t(n), v->f);
    if (got == 0) return std::ferror(v->f) ? AVERROR(EIO) : AVERROR_EOF;
    v->pos += std::int64_t(got);
    return int(got);
  }
  static std::int64_t seek(void* opaque, std::int64_t offset, int whence) {
    auto* v = static_cast<FileView*>(opaque);
    if (whence & AVSEEK_SIZE) return v->size;
    whence &= ~AVSEEK_FORCE;
    const std::int64_t to = whence == SEEK_SET ? offset : whence == SEEK_CUR ? v->pos + offset
                          : whence == SEEK_END ? v->size + offset : -1;
    if (to < 0) return AVERROR(EINVAL);
    v->pos = to;
    return to;
  }
};

}  // namespace

void check_mp4_options(const std::filesystem::path& path, const Mp4Options& options) {
  const auto where = [&] { return "MP4 '" + path.string() + "'"; };
  if (options.fps < 1 || options.fps > 1000)
    throw Error(where() + ": fps " + std::to_string(options.fps) + " is out of range (allowed 1..1000)");
  if (options.crf < 0 || options.crf > 51)
    throw Error(where() + ": crf " + std::to_string(options.crf) + " is out of range (allowed 0..51)");
  if (options.resume_frames < 0)
    throw Error(where() + ": resume_frames " + std::to_string(options.resume_frames) +
                " is negative (allowed 0 to start a new video, K > 0 to keep the first K frames of the .partial)");
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
  AVCodecContext* codec = nullptr;    // the x264 instance since the last sync()
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;
  Image padded;  // only for odd sizes: the frame with its last column/row repeated
  std::int64_t frames = 0;   // sent to an encoder, or kept from the resumed .partial
  std::int64_t packets = 0;  // given to the muxer
  std::int64_t on_disk = 0;  // in fragments the kernel holds: they survive SIGKILL
  std::int64_t encoder_frames = 0;  // sent to the current x264 instance: what sync() drains
  int delay = 0;                    // x264's B-frame delay in frames (codec->has_b_frames)
  std::vector<std::uint8_t> extradata;  // the first x264 instance's SPS/PPS (Annex B)
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
  void open_encoder();
  AVPixelFormat pixel_format() const { return options.chroma_444 ? AV_PIX_FMT_YUV444P : AV_PIX_FMT_YUV420P; }
  void open_muxer(const std::filesystem::path& file);
  void resume();
  void sync();
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
  // x264 prints its settings and statistics at info level; batch runs want warnings only.
  // A program that chose another level keeps it.
  if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_WARNING);

  // Found now rather than after the whole encode, when finish() renames onto it.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error(where() + ": the path names a directory, a file is needed");
  partial = path;
  partial += ".partial";

  open_encoder();
  extradata.assign(codec->extradata, codec->extradata + codec->extradata_size);
  // libavcodec's libx264 wrapper sets it from the B-frame settings: 2 with B-pyramid, 1
  // without, 0 without B-frames. Decode timestamps run that many frames behind.
  delay = codec->has_b_frames;

  if (options.resume_frames > 0) {
    resume();
  } else {
    open_muxer(partial);
    avio_flush(format->pb);
    if (format->pb->error < 0) fail_write(format->pb->error);
  }

  frame = av_frame_alloc();
  packet = av_packet_alloc();
  if (!frame || !packet) fail("out of memory allocating frames");
  frame->format = pixel_format();
  frame->width = enc_width;
  frame->height = enc_height;
  frame->color_range = AVCOL_RANGE_MPEG;
  frame->colorspace = AVCOL_SPC_BT709;
  frame->color_primaries = AVCOL_PRI_BT709;
  frame->color_trc = AVCOL_TRC_BT709;
  int err = av_frame_get_buffer(frame, 0);
  if (err < 0) fail("cannot allocate a video frame", err);

  sws = sws_getContext(enc_width, enc_height, AV_PIX_FMT_RGBA, enc_width, enc_height, pixel_format(),
                       SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr, nullptr);
  if (!sws) fail(std::string("swscale cannot convert RGBA to ") + av_get_pix_fmt_name(pixel_format()));
  // Full-range RGB in, limited-range BT.709 YCbCr out — matching the tags above.
  const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
  sws_setColorspaceDetails(sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);

  if (enc_width != width || enc_height != height) padded = Image(enc_width, enc_height);
  opened = true;
}

// A new x264 instance with the options, replacing the current one (after sync() drained it).
void Mp4Writer::Impl::open_encoder() {
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");  // checked by check_mp4_options
  avcodec_free_context(&codec);
  encoder_frames = 0;
  codec = avcodec_alloc_context3(encoder);
  if (!codec) fail("out of memory allocating the encoder");
  codec->width = enc_width;
  codec->height = enc_height;
  codec->pix_fmt = pixel_format();
  codec->time_base = AVRational{1, options.fps};
  codec->framerate = AVRational{options.fps, 1};
  codec->sample_aspect_ratio = AVRational{1, 1};
  codec->thread_count = options.threads;
  // Tag what swscale produces, so players do not guess BT.601 for HD.
  codec->color_range = AVCOL_RANGE_MPEG;
  codec->colorspace = AVCOL_SPC_BT709;
  codec->color_primaries = AVCOL_PRI_BT709;
  codec->color_trc = AVCOL_TRC_BT709;
  // MP4 keeps SPS/PPS in its header (avcC), not in the stream.
  if (av_guess_format("mp4", nullptr, nullptr)->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

  AVDictionary* codec_opts = nullptr;
  av_dict_set(&codec_opts, "preset", options.preset.c_str(), 0);
  av_dict_set_int(&codec_opts, "crf", options.crf, 0);
  int err = avcodec_open2(codec, encoder, &codec_opts);
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
}

// The fragmented muxer on `file` (created or truncated), its stream set up from the
// encoder, the header (empty index) written.
void Mp4Writer::Impl::open_muxer(const std::filesystem::path& file) {
  int err = avformat_alloc_output_context2(&format, nullptr, "mp4", file.c_str());
  if (err < 0 || !format) fail("cannot create the MP4 muxer", err);
  // No library version string and no creation time in the file: same frames, same bytes.
  format->flags |= AVFMT_FLAG_BITEXACT;

  stream = avformat_new_stream(format, nullptr);
  if (!stream) fail("out of memory allocating the stream");
  stream->time_base = codec->time_base;
  stream->avg_frame_rate = codec->framerate;
  err = avcodec_parameters_from_context(stream->codecpar, codec);
  if (err < 0) fail("cannot copy the encoder parameters", err);

  // Truncates a .partial that a killed earlier run left: this run's video replaces it.
  err = avio_open(&format->pb, file.c_str(), AVIO_FLAG_WRITE);
  if (err < 0) fail("cannot create '" + file.string() + "'", err);
  if (file == partial) partial_created = true;

  AVDictionary* mux_opts = nullptr;
  // empty_moov: the index (codec setup, no samples) goes first, so the file is playable
  // from the first fragment on. frag_custom: fragments are cut where drain() says, after
  // every frame. default_base_moof: offsets relative to each fragment, the form browsers'
  // Media Source Extensions require and every demuxer reads.
  av_dict_set(&mux_opts, "movflags", "frag_custom+empty_moov+default_base_moof", 0);
  err = avformat_write_header(format, &mux_opts);
  av_dict_free(&mux_opts);
  if (err < 0) fail("cannot write the MP4 header to '" + file.string() + "'", err);
}

// Options::resume_frames = K: a new .partial with the old one's first K packets, copied
// (see the header). The packets come back from the MP4 demuxer length-prefixed (avcC); the
// muxer takes this stream's packets in x264's Annex B form and converts them itself, so they
// are turned back into Annex B: the muxer then writes exactly the bytes it wrote the first
// time. Timestamps: the fragmented muxer shifted them by x264's first dts (it writes no edit
// list), which the copy removes, so the new muxer shifts them the same way again.
void Mp4Writer::Impl::resume() {
  const std::int64_t K = options.resume_frames;
  const std::string old = partial.string();
  const std::string k_frames = std::to_string(K) + (K == 1 ? " frame" : " frames");
  std::error_code ec;
  if (!std::filesystem::exists(partial, ec))
    fail("the video '" + old + "' is missing: cannot continue it (the checkpoint needs its first " + k_frames + ")");
  const auto cannot = [&](const std::string& why) -> void {
    fail("cannot continue the video '" + old + "' after its first " + k_frames + ": " + why);
  };

  AVFormatContext* in = nullptr;
  AVIOContext* io = nullptr;
  FileView view;
  AVPacket* pkt = av_packet_alloc();
  std::filesystem::path temp = partial;
  temp += ".resuming";
  bool renamed = false;
  struct Cleanup {
    Impl& m;
    AVFormatContext*& in;
    AVIOContext*& io;
    FileView& view;
    AVPacket*& pkt;
    const std::filesystem::path& temp;
    bool& renamed;
    ~Cleanup() {
      av_packet_free(&pkt);
      avformat_close_input(&in);
      if (io) av_freep(&io->buffer);
      avio_context_free(&io);
      if (view.f) std::fclose(view.f);
      if (!renamed) {
        // The old .partial stays as it was; the half copy goes.
        if (m.format) {
          if (m.format->pb) avio_closep(&m.format->pb);
          avformat_free_context(m.format);
          m.format = nullptr;
          m.stream = nullptr;
        }
        std::error_code ec;
        std::filesystem::remove(temp, ec);
      }
    }
  } cleanup{*this, in, io, view, pkt, temp, renamed};
  if (!pkt) fail("out of memory allocating a packet");

  // Only its complete boxes: what a kill tore at the end is left out (see complete_boxes).
  view.f = std::fopen(old.c_str(), "rb");
  if (!view.f) cannot(std::string("it cannot be opened (") + std::strerror(errno) + ")");
  const std::int64_t file_size = std::int64_t(std::filesystem::file_size(partial, ec));
  view.size = ec ? 0 : complete_boxes(view.f, file_size);
  constexpr int io_size = 1 << 16;
  auto* io_buffer = static_cast<unsigned char*>(av_malloc(io_size));
  if (io_buffer) io = avio_alloc_context(io_buffer, io_size, 0, &view, &FileView::read, nullptr, &FileView::seek);
  if (!io) {
    av_free(io_buffer);
    fail("out of memory allocating a reader");
  }
  in = avformat_alloc_context();
  if (!in) fail("out of memory allocating a reader");
  in->pb = io;
  int err = avformat_open_input(&in, old.c_str(), av_find_input_format("mp4"), nullptr);
  if (err < 0) cannot("it cannot be read (" + av_reason(err) + ")");
  if (in->nb_streams != 1 || in->streams[0]->codecpar->codec_type != AVMEDIA_TYPE_VIDEO)
    cannot("it does not hold one video stream");
  const AVStream* is = in->streams[0];
  const AVCodecParameters* par = is->codecpar;
  if (par->codec_id != AV_CODEC_ID_H264)
    cannot(std::string("its codec is ") + avcodec_get_name(par->codec_id) + ", not H.264");
  if (par->width != enc_width || par->height != enc_height)
    cannot("it is " + std::to_string(par->width) + "x" + std::to_string(par->height) + " but the frames are " +
           std::to_string(width) + "x" + std::to_string(height) +
           (enc_width != width || enc_height != height
                ? " (encoded " + std::to_string(enc_width) + "x" + std::to_string(enc_height) + ")"
                : std::string()));
  const AVRational in_tb = is->time_base;
  const AVRational tb = codec->time_base;
  // The first packet (frame 0) tells the frame rate: every frame lasts 1 / fps.
  bool have = av_read_frame(in, pkt) >= 0;
  if (have && pkt->duration > 0 && pkt->duration * in_tb.num * options.fps != in_tb.den) {
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", double(in_tb.den) / double(pkt->duration * in_tb.num));
    cannot(std::string("its frame rate is ") + rate + " frames/s, not " + std::to_string(options.fps));
  }
  const auto old_sets = parameter_sets(par->extradata, par->extradata_size);
  const auto new_sets = parameter_sets(codec->extradata, codec->extradata_size);
  if (!old_sets || par->extradata_size < 5 || (par->extradata[4] & 3) != 3)
    cannot("its H.264 header (avcC) is not the form this writer makes");
  if (!new_sets || !(*old_sets == *new_sets))
    cannot("its H.264 parameter sets (SPS/PPS) differ from this run's encoder's (preset '" + options.preset +
           "', crf " + std::to_string(options.crf) +
           "): another preset or x264 version made it, and one MP4 track holds one set");

  open_muxer(temp);
  std::int64_t n = 0, shift = 0;
  std::vector<bool> seen;  // frames copied, by index
  while (n < K) {
    if (!have && av_read_frame(in, pkt) < 0) break;  // the end, or the fragment the kill tore
    have = false;
    // A packet cut by the end of the file: the kill tore its fragment.
    if ((pkt->flags & AV_PKT_FLAG_CORRUPT) || pkt->size <= 0) break;
    // Back to Annex B: each 4-byte length becomes a 4-byte start code.
    if (av_packet_make_writable(pkt) < 0) fail("out of memory copying a packet");
    int at = 0;
    while (at + 4 <= pkt->size) {
      const std::uint32_t len = std::uint32_t(pkt->data[at]) << 24 | std::uint32_t(pkt->data[at + 1]) << 16 |
                                std::uint32_t(pkt->data[at + 2]) << 8 | pkt->data[at + 3];
      pkt->data[at] = pkt->data[at + 1] = pkt->data[at + 2] = 0;
      pkt->data[at + 3] = 1;
      if (len > std::uint32_t(pkt->size - at - 4)) break;
      at += 4 + int(len);
    }
    if (at != pkt->size) break;  // cut inside a NAL unit: torn
    const std::int64_t pts = av_rescale_q(pkt->pts, in_tb, tb), dts = av_rescale_q(pkt->dts, in_tb, tb);
    if (n == 0) shift = pts;  // frame 0 is first in decode order
    const std::int64_t frame_pts = pts - shift, frame_dts = dts - shift;
    const bool in_prefix = frame_pts >= 0 && frame_pts < K;
    if (in_prefix && std::size_t(frame_pts) >= seen.size()) seen.resize(std::size_t(frame_pts) + 1, false);
    if (av_rescale_q(pts, tb, in_tb) != pkt->pts || !in_prefix || seen[std::size_t(frame_pts)] ||
        frame_dts != n - delay)
      cannot("its packet " + std::to_string(n) + " in decode order is frame " + std::to_string(frame_pts) +
             " (decoded at " + std::to_string(frame_dts) + "): frames 0.." + std::to_string(K - 1) +
             " are not its first " + k_frames + ", so it was not synced at frame " + std::to_string(K) +
             " (another checkpoint's or another writer's video)");
    seen[std::size_t(frame_pts)] = true;
    av_packet_free_side_data(pkt);
    pkt->pts = frame_pts;
    pkt->dts = frame_dts;
    pkt->duration = 1;
    av_packet_rescale_ts(pkt, tb, stream->time_base);
    pkt->stream_index = stream->index;
    pkt->pos = -1;
    err = av_write_frame(format, pkt);
    av_packet_unref(pkt);
    if (err >= 0) err = av_write_frame(format, nullptr);  // a fragment per frame, as the first time
    if (err < 0 || format->pb->error < 0)
      fail("cannot write '" + temp.string() + "': " + av_reason(err < 0 ? err : format->pb->error) +
           "; the video '" + old + "' is left as it was");
    ++n;
  }
  av_packet_unref(pkt);
  if (n < K) cannot("it holds " + std::to_string(n) + " frames, the checkpoint needs " + std::to_string(K));
  avio_flush(format->pb);
  if (format->pb->error < 0)
    fail("cannot write '" + temp.string() + "': " + av_reason(format->pb->error) + "; the video '" + old +
         "' is left as it was");
  std::filesystem::rename(temp, partial, ec);
  if (ec) fail("cannot rename '" + temp.string() + "' to '" + old + "': " + ec.message() + "; the video is left as it was");
  renamed = true;
  partial_created = true;
  frames = packets = on_disk = K;
}

// Drains the current x264 instance into the .partial and starts a new one (see the header).
void Mp4Writer::Impl::sync() {
  if (encoder_frames == 0) return;  // nothing inside x264; its state is already the start's
  int err = avcodec_send_frame(codec, nullptr);
  if (err < 0) fail("cannot flush the encoder", err);
  drain(true);
  open_encoder();
  if (codec->extradata_size != int(extradata.size()) ||
      !std::equal(extradata.begin(), extradata.end(), codec->extradata))
    fail("a new libx264 instance made other H.264 parameter sets (SPS/PPS) than the first one; one MP4 track "
         "holds one set, so the video cannot continue");
  if (codec->has_b_frames != delay) fail("a new libx264 instance has another B-frame delay than the first one");
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
    // Packet n (in decode order, over all x264 instances) decodes at n - delay: what x264
    // computes itself for an instance that got more than `delay` frames, and the value that
    // keeps dts increasing from one instance to the next when it got fewer (x264 then
    // gives dts = pts, and the next instance's first dts would go back).
    packet->dts = packets - delay;
    if (packet->pts < packet->dts)
      fail("libx264 gave frame " + std::to_string(packet->pts) + " a decode time after its presentation time");
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
  ++m.encoder_frames;
  m.drain(false);
}

void Mp4Writer::sync() {
  Impl& m = *impl_;
  m.throw_if_failed();
  if (m.finished) throw Error(m.where() + ": sync() after finish()");
  m.sync();
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
