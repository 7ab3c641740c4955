// H.264 MP4 encoding of RGBA8 frames with libx264 through FFmpeg (libavcodec, libavformat,
// libswscale): yuv420p, BT.709 tagged, odd sizes padded to even (SPEC.md §3, "Outputs":
// H.264 MP4). Fault-safe: a killed run keeps its video up to the last few frames (#12).
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "render/image/image.hpp"

namespace grainflow::render {

struct Mp4Options {
  int fps = 30;  // constant frame rate; frame k is shown at k / fps seconds
  int crf = 20;  // x264 constant rate factor, 0 (lossless) .. 51; 18-23 looks clean
  // x264 preset. superfast: ~50 ms CPU per 1920x1080 frame (crf 20, 2 threads), so ~40
  // frames/s on this 2-core machine when idle and 20 frames/s on one core; veryfast needs
  // ~86 ms (<= ~23 frames/s with both cores, nothing left for the simulation) for files
  // ~40% smaller; ultrafast ~26 ms but files 1.5x larger than superfast's. Figures from
  // tests/bench/bench_encode.cpp.
  std::string preset = "superfast";
  int threads = 2;  // encoder threads; the machine is shared, the renderer needs a core
  // Full-resolution colour (yuv444p, x264's High 4:4:4 profile) for analysis copies: 4:2:0
  // halves the chroma resolution, which smears 1-pixel disks and bin edges. With crf 0 the
  // video is lossless. Browsers and many hardware players cannot play 4:4:4; ffmpeg, VLC
  // and mpv can.
  bool chroma_444 = false;
  // Resume (`grainflow run --resume`): 0 starts a new video (a .partial left by an earlier
  // run is replaced). K > 0 continues the `<path>.partial` that a killed run left: its first
  // K frames are kept, copied as packets without re-encoding, and the first frame written
  // is frame K. That run must have called sync() with exactly K frames written (the
  // checkpoint); the frames it encoded after that, and a fragment torn by the kill, are
  // dropped. See Mp4Writer's constructor for the checks.
  std::int64_t resume_frames = 0;
};

// Throws grainflow::Error naming `path`, the option, its value and what is allowed, or
// the missing libx264 encoder. Mp4Writer calls it; sinks call it early to fail fast. It does
// not look at the .partial a resume needs: that is checked when the writer opens.
void check_mp4_options(const std::filesystem::path& path, const Mp4Options& options);

// Encodes frames of one fixed size into `path`, in two stages (issue #12, "Faults keep what
// was computed"):
//  - While encoding, the video is `<path>.partial`: a fragmented MP4 (an empty index, then
//    one fragment per frame, each passed to the kernel as soon as x264 emits it). It is a
//    valid MP4 at every fragment boundary, so after SIGKILL, SIGHUP, a crash or a full
//    disk it plays (ffmpeg/ffprobe checked; players that probe the content, as VLC and mpv
//    do, too) with every frame but those still inside x264: 9 with the default options
//    (3 B-frames and their lookahead, 2 frame threads), 16 for veryfast, 46 for medium
//    (its 40-frame rate-control lookahead). A fragment per frame costs ~120 bytes a frame
//    (+0.1% at 1080p); fragments at keyframes would lose up to a whole GOP besides and need
//    a short one: keyint 30 (1 s) costs +4% in size at 1080p (tests/bench/bench_encode.cpp,
//    notes). `.partial` is the project's name for "usable but not finished"
//    (stats.csv.partial): a killed run leaves it beside where the video would be,
//    `grainflow run --force` removes it, and `path` itself never names an unfinished
//    video. Nothing is fsync'ed: a killed process loses nothing the kernel has; a power
//    cut is not covered.
//  - finish() closes it and copies the packets, without re-encoding, into a standard MP4
//    with the index in front (+faststart: what QuickTime, browsers streaming a file and
//    frame counts from the index expect), written under an io::AtomicFile temporary and
//    renamed to `path`; the .partial is then removed. The copy reads and writes the file
//    once more (~1-2 ms per MB from the page cache: 40-60 ms for 300 1080p frames) and needs the
//    room for a second copy while it runs. Killed during it, the complete .partial stays;
//    failing (a full disk), the error says the complete video is in the .partial.
//  - sync() (checkpoints, `grainflow run --resume`) drains x264, so every frame written so
//    far is in the .partial's fragments, and continues with a new x264 instance (same
//    options, same stream, frame k still at k / fps) that starts with an IDR frame. The
//    .partial then holds exactly frames 0..K-1 (K = frames_written()) as the first K
//    packets in decode order, self-contained (H.264 references only earlier-decoded
//    frames), and every later packet belongs to frames >= K: what a resume with
//    Mp4Options::resume_frames = K keeps. (FFmpeg 5.1's libx264 cannot be flushed and
//    continued, AV_CODEC_CAP_ENCODER_FLUSH, hence the new instance.) A sync waits for
//    x264 to encode the ~9 frames in its pipeline (~0.33 s at 1080p, ~0.16 s at 720p), and
//    the IDR frame that starts each instance makes the file larger: a sync every 30 frames
//    costs +5.5% at 1080p and +1.4% at 720p, every 100 frames +0.7% and +1.2%
//    (`bench_encode sync`, tests/bench/bench_encode.cpp). The SPS/PPS of every instance are
//    checked to equal the first one's (the MP4 track has one set).
//    Decode timestamps stay strictly increasing across the instances: the writer sets
//    packet n's dts to n - (B-frame delay) in frame units, which is what x264 computes for
//    an instance given more than its delay frames, and what it does not for fewer (a sync
//    1 or 2 frames after the previous one: x264 then gives dts = pts, and the next
//    instance's first dts would go back).
//  - With resume_frames = K, the writer reads the .partial a killed run left and writes a
//    new one under `<path>.partial.resuming` holding its first K packets, then renames it
//    over `<path>.partial` once they are all there (killed before, the old .partial is
//    intact and the next resume starts again; `.resuming` is overwritten). Frames K, K+1,
//    ... follow as written. Only the old file's complete top-level boxes are read: a kill
//    that tore a fragment header would make libavformat refuse the whole file. The result
//    is byte for byte the file a run that was never killed writes with the same frames and
//    sync points. The copy takes ~30-65 ms for 300 1080p frames (38 MB).
// Destroyed without finish() (an exception elsewhere ended the run), the frames still in
// the encoder are flushed into the .partial, which is closed and kept. After an encoder or
// I/O error it is kept as it is if some frames reached the disk (the error says how many),
// and removed if none did, so what remains is never misleading. Same frames and options
// give the same bytes in both files (no clocks, no library versions: bitexact muxing).
class Mp4Writer {
public:
  // Width and height are the frame size; odd values are padded to even by repeating the
  // last column/row (yuv420p needs even sizes). Throws grainflow::Error if libx264 is not
  // available, an option is out of range, or the file cannot be created.
  // With options.resume_frames = K > 0 (see Mp4Options), it also throws grainflow::Error
  // when `<path>.partial` is missing ("the video '...' is missing: cannot continue it"),
  // holds fewer than K complete frames ("holds N frames, the checkpoint needs K"), has
  // another codec, frame size (after padding to even) or frame rate than this writer,
  // encoder settings whose SPS/PPS differ from the new encoder's (another preset, x264 or
  // libavcodec version), or frames 0..K-1 not as its first K packets (it was not synced at
  // K: another checkpoint's video). The old .partial is then left as it was.
  Mp4Writer(std::filesystem::path path, int width, int height, Mp4Options options = {});
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // Frame size must match the constructor's. Throws grainflow::Error on encoder/IO errors.
  void write(const Image& frame);
  // Puts every frame written so far into the .partial (handed to the kernel, not fsync'ed)
  // as a prefix that a resume with resume_frames = frames_written() continues; see above.
  // Afterwards frames_on_disk() == frames_written(). With no frame written since the last
  // sync() (or since the start or the resume point) it does nothing. Throws grainflow::Error
  // on encoder/IO errors, after finish(), or if the new x264 instance's SPS/PPS differ from
  // the first one's (one MP4 track has one set; never seen with the same options).
  void sync();
  // Flushes the encoder, closes the .partial and publishes the standard MP4 under `path`
  // (see above). Further write()/finish() calls are errors. After a failure the complete
  // video stays in the .partial and the error says so.
  void finish();

  // After the first encoder or I/O error, write() and finish() throw that error again:
  // the first cause is the one reported, not what it broke afterwards.

  std::int64_t frames_written() const;
  // Frames in fragments already handed to the kernel: what a SIGKILL now would keep.
  std::int64_t frames_on_disk() const;
  // `<path>.partial`, where the video is until finish() has published it.
  const std::filesystem::path& partial_path() const;
  int encoded_width() const;   // padded to even
  int encoded_height() const;  // padded to even

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace grainflow::render
