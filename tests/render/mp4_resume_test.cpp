// Checkpoints and `grainflow run --resume` for the MP4 output: Mp4Writer::sync() leaves a
// resumable prefix in the .partial, and Mp4Options::resume_frames continues a .partial that
// a killed run left, so the folder ends with one playable MP4 of every frame.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/output/async_sink.hpp"
#include "render/output/fan_out_sink.hpp"
#include "render/output/mp4_sink.hpp"
#include "render/output/mp4_writer.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "mp4_test_support.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

namespace fs = std::filesystem;
using test::av_errors_during;
using test::decodable_frames;
using test::decode;
using test::Decoded;
using test::ffmpeg_decode_errors;
using test::ffprobe;
using test::fresh_dir;
using test::psnr_rgb;
using test::slurp;
using test::smooth_pattern;

// A picture that tells frame `k` (0..71) of run `run` apart from every other one after
// H.264: one flat colour, red and blue counting frames, green naming the run.
std::uint8_t solid_channel(int k, int run, int c) {
  if (c == 0) return static_cast<std::uint8_t>(16 + 9 * (k % 24));
  if (c == 1) return static_cast<std::uint8_t>(run == 0 ? 50 : 200);
  return static_cast<std::uint8_t>(40 + 70 * ((k / 24) % 3));
}

Image solid(int w, int h, int k, int run) {
  Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = im.pixel(x, y);
      for (int c = 0; c < 3; ++c) p[c] = solid_channel(k, run, c);
      p[3] = 255;
    }
  return im;
}

// The largest difference of the mean R, G, B of `a` from the colour of solid(k, run).
double solid_error(const Image& a, int k, int run) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    double sum = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) sum += a.pixel(x, y)[c];
    worst = std::max(worst, std::abs(sum / (double(a.width) * a.height) - solid_channel(k, run, c)));
  }
  return worst;
}

// Which solid(k, run) a decoded frame shows: the nearest colour (adjacent ones are 9 levels
// apart; the RGB -> BT.709 yuv420p -> RGB round trip moves flat colours by 3-4 levels).
void expect_shows(const Image& decoded, int k, int run) {
  int best_k = -1, best_run = -1;
  double best = 1e9;
  for (int r = 0; r < 2; ++r)
    for (int j = 0; j < 72; ++j)
      if (const double e = solid_error(decoded, j, r); e < best) best = e, best_k = j, best_run = r;
  EXPECT_TRUE(best_k == k && best_run == run) << "frame " << k << " of run " << run << " shows frame " << best_k
                                              << " of run " << best_run;
  EXPECT_LT(solid_error(decoded, k, run), 6.0) << "frame " << k;
}

// The frame number in binary along the top edge: 6 macroblocks, black for 0, white for 1.
void stamp(Image& im, int k) {
  for (int bit = 0; bit < 6; ++bit)
    for (int y = 0; y < 16; ++y)
      for (int x = 16 * bit; x < 16 * bit + 16; ++x) {
        std::uint8_t* p = im.pixel(x, y);
        p[0] = p[1] = p[2] = (k >> bit & 1) ? 255 : 0;
      }
}
int read_stamp(const Image& im) {
  int k = 0;
  for (int bit = 0; bit < 6; ++bit) {
    double sum = 0;
    for (int y = 4; y < 12; ++y)
      for (int x = 16 * bit + 4; x < 16 * bit + 12; ++x) sum += im.pixel(x, y)[1];
    if (sum / 64 > 128) k |= 1 << bit;
  }
  return k;
}

// The file decoded, with what the decoder logged at error level (must be nothing), and the
// same from ffmpeg and ffprobe where they are installed.
struct Checked {
  Decoded d;
  std::string errors;
};
Checked decode_checked(const fs::path& path, std::int64_t expect_frames) {
  Checked c;
  c.errors = av_errors_during([&] { c.d = decode(path); });
  EXPECT_EQ(c.errors, "") << path;
  EXPECT_EQ(std::int64_t(c.d.frames.size()), expect_frames) << path;
  if (test::ffmpeg_installed()) {
    EXPECT_EQ(ffmpeg_decode_errors(path), "") << "ffmpeg -v error -i " << path << " -f null -";
    EXPECT_EQ(ffprobe("-count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0", path),
              std::to_string(expect_frames))
        << path;
  }
  return c;
}

// Decode timestamps strictly increasing, presentation times exactly frames 0..n-1 (in the
// container's clock, less the first frame's), as the muxer and players need.
void expect_timestamps_in_order(const fs::path& path, std::int64_t n) {
  AVFormatContext* fmt = nullptr;
  ASSERT_EQ(avformat_open_input(&fmt, path.c_str(), nullptr, nullptr), 0);
  AVPacket* pkt = av_packet_alloc();
  std::vector<std::int64_t> pts;
  std::int64_t last_dts = INT64_MIN;
  const AVRational tb = fmt->streams[0]->time_base;
  while (av_read_frame(fmt, pkt) >= 0) {
    EXPECT_GT(pkt->dts, last_dts) << "packet " << pts.size();
    EXPECT_LE(pkt->dts, pkt->pts) << "packet " << pts.size();
    last_dts = pkt->dts;
    pts.push_back(pkt->pts);
    av_packet_unref(pkt);
  }
  av_packet_free(&pkt);
  avformat_close_input(&fmt);
  ASSERT_EQ(std::int64_t(pts.size()), n);
  std::sort(pts.begin(), pts.end());
  const double frame = 1.0 / 30;
  for (std::int64_t k = 0; k < n; ++k)
    EXPECT_NEAR(double(pts[std::size_t(k)] - pts[0]) * av_q2d(tb), double(k) * frame, 1e-6) << "frame " << k;
}

// A copy of the .partial as it is now: what a kill at this moment would leave.
std::int64_t frames_in_copy(const fs::path& partial, const fs::path& copy) {
  fs::copy_file(partial, copy, fs::copy_options::overwrite_existing);
  return decodable_frames(copy);
}

Mp4Options opts(const std::string& preset = "superfast", std::int64_t resume = 0) {
  Mp4Options o;
  o.preset = preset;
  o.resume_frames = resume;
  return o;
}

TEST(Mp4Sync, MidwayPutsEveryFrameOnDiskAndTheVideoContinues) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "sync.mp4";
  const int w = 160, h = 96;
  std::vector<Image> src;
  for (int k = 0; k < 45; ++k) {
    src.push_back(smooth_pattern(w, h, 0.2 * k));
    stamp(src.back(), k);
  }
  {
    Mp4Writer writer(path, w, h, opts());
    for (int k = 0; k < 25; ++k) writer.write(src[std::size_t(k)]);
    EXPECT_LT(writer.frames_on_disk(), 25) << "x264 holds some frames";
    writer.sync();
    EXPECT_EQ(writer.frames_written(), 25);
    EXPECT_EQ(writer.frames_on_disk(), 25);
    // A kill now would leave exactly these 25 frames, complete and in order.
    fs::copy_file(writer.partial_path(), dir / "at25.mp4");
    for (int k = 25; k < 45; ++k) writer.write(src[std::size_t(k)]);
    writer.finish();
  }
  const Checked at25 = decode_checked(dir / "at25.mp4", 25);
  for (int k = 0; k < 25; ++k) EXPECT_GT(psnr_rgb(src[std::size_t(k)], at25.d.frames[std::size_t(k)]), 35.0) << k;

  const Checked c = decode_checked(path, 45);
  EXPECT_EQ(c.d.nb_frames_field, 45);
  EXPECT_NEAR(c.d.duration_s, 45.0 / 30, 0.5 / 30);
  EXPECT_EQ(c.d.start_s, 0.0);
  ASSERT_EQ(c.d.frames.size(), 45u);
  for (int k = 0; k < 45; ++k)
    EXPECT_GT(psnr_rgb(src[std::size_t(k)], c.d.frames[std::size_t(k)]), 35.0) << "frame " << k;
  // In order, across the sync too.
  for (int k = 0; k < 45; ++k) EXPECT_EQ(read_stamp(c.d.frames[std::size_t(k)]), k);
  for (int k = 0; k < 25; ++k) EXPECT_EQ(read_stamp(at25.d.frames[std::size_t(k)]), k);
  expect_timestamps_in_order(path, 45);
}

// Syncs that find nothing to drain (at frame 0, twice in a row) do nothing; syncs 1, 2 and
// 3 frames apart give x264 instances shorter than its B-frame delay (x264 then stamps
// dts = pts); every preset's delay (ultrafast: no B-frames; superfast/medium: B-pyramid).
TEST(Mp4Sync, AtFrameZeroTwiceInARowAndFewFramesApart) {
  for (const std::string preset : {"ultrafast", "superfast", "medium"}) {
    SCOPED_TRACE(preset);
    const fs::path dir = fresh_dir();
    const fs::path path = dir / "many.mp4";
    const int w = 96, h = 64;
    std::vector<Image> src;
    {
      Mp4Writer writer(path, w, h, opts(preset));
      writer.sync();  // nothing written yet
      EXPECT_EQ(writer.frames_on_disk(), 0);
      const auto put = [&](int n) {
        for (int i = 0; i < n; ++i) {
          src.push_back(smooth_pattern(w, h, 0.25 * double(src.size())));
          writer.write(src.back());
        }
      };
      int copies = 0;
      const auto sync_and_check = [&] {
        writer.sync();
        EXPECT_EQ(writer.frames_on_disk(), writer.frames_written());
        EXPECT_EQ(frames_in_copy(writer.partial_path(), dir / ("copy" + std::to_string(copies++) + ".mp4")),
                  writer.frames_written());
      };
      put(10);
      sync_and_check();
      sync_and_check();  // twice in a row
      put(1);
      sync_and_check();
      put(2);
      sync_and_check();
      put(3);
      sync_and_check();
      put(1);
      sync_and_check();
      put(7);
      writer.finish();
    }
    const std::int64_t n = std::int64_t(src.size());
    const Checked c = decode_checked(path, n);
    ASSERT_EQ(std::int64_t(c.d.frames.size()), n);
    for (std::int64_t k = 0; k < n; ++k)
      EXPECT_GT(psnr_rgb(src[std::size_t(k)], c.d.frames[std::size_t(k)]), 33.0) << "frame " << k;
    expect_timestamps_in_order(path, n);
    for (int i = 0; i < 6; ++i) {
      const fs::path copy = dir / ("copy" + std::to_string(i) + ".mp4");
      EXPECT_EQ(av_errors_during([&] { decode(copy); }), "") << copy;
    }
  }
}

TEST(Mp4Sync, AfterFinishIsAnError) {
  const fs::path dir = fresh_dir();
  Mp4Writer writer(dir / "x.mp4", 64, 48, opts("ultrafast"));
  writer.write(smooth_pattern(64, 48, 0));
  writer.finish();
  EXPECT_THROW(writer.sync(), Error);
}

// Same frames and sync points: the same bytes, in the .partial and in the final MP4.
TEST(Mp4Sync, SameFramesAndSyncPointsGiveTheSameBytes) {
  const fs::path dir = fresh_dir();
  std::string partials[2];
  for (int run = 0; run < 2; ++run) {
    Mp4Writer writer(dir / (std::to_string(run) + ".mp4"), 96, 64);
    for (int k = 0; k < 40; ++k) {
      writer.write(smooth_pattern(96, 64, 0.3 * k));
      if (k + 1 == 12 || k + 1 == 13 || k + 1 == 30) writer.sync();
    }
    writer.sync();
    partials[run] = slurp(writer.partial_path());
    writer.finish();
  }
  EXPECT_FALSE(partials[0].empty());
  EXPECT_TRUE(partials[0] == partials[1]);
  const std::string a = slurp(dir / "0.mp4"), b = slurp(dir / "1.mp4");
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == b);
}

// The child encodes frames 0..19 of run 0, syncs (the checkpoint at 20), encodes 20..36 and
// is SIGKILLed; the parent resumes at 20 and writes frames 20..44 of run 1.
TEST(Mp4Resume, KilledRunContinuesFromItsCheckpoint) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "run.mp4";
  const fs::path partial = path.string() + ".partial";
  const int w = 128, h = 80, K = 20, killed_at = 37, n = 45;
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    close(fds[0]);
    try {
      Mp4Writer writer(path, w, h);  // the default options, as scenes use them
      for (int k = 0; k < killed_at; ++k) {
        writer.write(solid(w, h, k, 0));
        if (k + 1 == K) writer.sync();
      }
      const std::int64_t on_disk = writer.frames_on_disk();
      if (write(fds[1], &on_disk, sizeof on_disk) != ssize_t(sizeof on_disk)) _exit(3);
      for (;;) pause();  // never finish(): the parent kills this process
    } catch (...) {
      _exit(2);
    }
  }
  close(fds[1]);
  std::int64_t on_disk = 0;
  const ssize_t got = read(fds[0], &on_disk, sizeof on_disk);
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  close(fds[0]);
  ASSERT_EQ(got, ssize_t(sizeof on_disk)) << "the child failed, wait status " << status;
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  // The killed run's .partial holds frames past the checkpoint: the resume must drop them.
  EXPECT_GT(on_disk, K);
  EXPECT_GE(decodable_frames(partial), on_disk);

  {
    Mp4Writer writer(path, w, h, opts("superfast", K));
    EXPECT_EQ(writer.frames_written(), K);
    EXPECT_EQ(writer.frames_on_disk(), K);
    EXPECT_EQ(frames_in_copy(partial, dir / "resumed.copy"), K) << "the new .partial: the checkpoint's frames";
    EXPECT_FALSE(fs::exists(partial.string() + ".resuming"));
    for (int k = K; k < n; ++k) writer.write(solid(w, h, k, 1));
    writer.finish();
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2) << "the MP4 and the copy";
  const Checked c = decode_checked(path, n);
  ASSERT_EQ(int(c.d.frames.size()), n);
  for (int k = 0; k < n; ++k) expect_shows(c.d.frames[std::size_t(k)], k, k < K ? 0 : 1);
  EXPECT_EQ(c.d.nb_frames_field, n);
  EXPECT_NEAR(c.d.duration_s, double(n) / 30, 0.5 / 30);
  expect_timestamps_in_order(path, n);
}

// A kill in the middle of a fragment after the checkpoint leaves a torn last packet, or a
// torn fragment header; cut exactly at the checkpoint, the file holds just its frames.
TEST(Mp4Resume, PartialTornAnywhereAfterTheCheckpoint) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "torn.mp4";
  const fs::path partial = path.string() + ".partial";
  const int w = 96, h = 64, K = 12;
  std::uintmax_t at_checkpoint = 0;
  {
    Mp4Writer writer(path, w, h);
    for (int k = 0; k < K; ++k) writer.write(solid(w, h, k, 0));
    writer.sync();
    at_checkpoint = fs::file_size(partial);
    for (int k = K; k < 25; ++k) writer.write(solid(w, h, k, 0));
    writer.sync();
  }  // dropped unfinished
  const std::uintmax_t size = fs::file_size(partial);
  fs::copy_file(partial, dir / "whole");
  for (const std::uintmax_t cut : {at_checkpoint, at_checkpoint + 1, at_checkpoint + 9, at_checkpoint + 30,
                                   (at_checkpoint + size) / 2, size - 7}) {
    SCOPED_TRACE("cut at " + std::to_string(cut) + " of " + std::to_string(size) + " bytes");
    fs::copy_file(dir / "whole", partial, fs::copy_options::overwrite_existing);
    fs::resize_file(partial, cut);
    EXPECT_GE(decodable_frames(partial), K);
    {
      Mp4Writer writer(path, w, h, opts("superfast", K));
      for (int k = K; k < 20; ++k) writer.write(solid(w, h, k, 1));
      writer.finish();
    }
    const Checked c = decode_checked(path, 20);
    for (int k = 0; k < int(c.d.frames.size()); ++k) expect_shows(c.d.frames[std::size_t(k)], k, k < K ? 0 : 1);
    fs::remove(path);
  }
  // Every cut inside the first fragment after the checkpoint (its moof, mdat header and
  // first bytes), where libavformat alone cannot even open the file: ffprobe says "error
  // reading header" for a torn moof, as it reads every fragment header at the start.
  for (std::uintmax_t cut = at_checkpoint + 1; cut < at_checkpoint + 160; ++cut) {
    fs::copy_file(dir / "whole", partial, fs::copy_options::overwrite_existing);
    fs::resize_file(partial, cut);
    try {
      Mp4Writer writer(path, w, h, opts("superfast", K));
      writer.write(solid(w, h, K, 1));
      writer.finish();
    } catch (const Error& e) {
      ADD_FAILURE() << "cut at " << cut << ": " << e.what();
      continue;
    }
    EXPECT_EQ(decodable_frames(path), K + 1) << "cut at " << cut;
    fs::remove(path);
  }
}

// A resumed run writes the bytes of a run that was never stopped: the copy reproduces the
// first run's fragments exactly, and x264 instances with the same options and frames agree.
TEST(Mp4Resume, GivesTheBytesOfARunThatWasNeverStopped) {
  const fs::path dir = fresh_dir();
  const int w = 96, h = 64, K = 20, n = 45;
  const auto frame = [&](int k) { return smooth_pattern(w, h, 0.3 * k); };
  std::string whole_partial;
  {
    Mp4Writer writer(dir / "whole.mp4", w, h);
    for (int k = 0; k < n; ++k) {
      writer.write(frame(k));
      if (k + 1 == 8 || k + 1 == K) writer.sync();
    }
    writer.sync();
    whole_partial = slurp(writer.partial_path());
    writer.finish();
  }
  {
    Mp4Writer writer(dir / "resumed.mp4", w, h);
    for (int k = 0; k < 33; ++k) {
      writer.write(frame(k));
      if (k + 1 == 8 || k + 1 == K) writer.sync();
    }
  }  // stopped: the .partial holds 33 frames and a closing index
  std::string resumed_partial;
  {
    Mp4Writer writer(dir / "resumed.mp4", w, h, opts("superfast", K));
    for (int k = K; k < n; ++k) writer.write(frame(k));
    writer.sync();
    resumed_partial = slurp(writer.partial_path());
    writer.finish();
  }
  EXPECT_EQ(resumed_partial.size(), whole_partial.size());
  EXPECT_TRUE(resumed_partial == whole_partial) << "the .partial";
  const std::string a = slurp(dir / "whole.mp4"), b = slurp(dir / "resumed.mp4");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "the final MP4";
}

// A run that finished (its standard MP4 published) and is then extended, or resumed from an
// earlier checkpoint: scenes rename the MP4 back to the .partial, and the copy reads the
// standard MP4 (one index, edit list for the B-frame delay) as it reads a fragmented one.
TEST(Mp4Resume, FromAFinishedStandardMp4) {
  const fs::path dir = fresh_dir();
  const int w = 96, h = 64, n = 30, more = 12;
  const auto frame = [&](int k) { return smooth_pattern(w, h, 0.3 * k); };
  for (const int K : {20, n}) {
    SCOPED_TRACE("resumed at " + std::to_string(K));
    const fs::path ref = dir / "reference.mp4", path = dir / "run.mp4";
    {
      Mp4Writer writer(ref, w, h);  // never stopped: syncs at 20 and K
      for (int k = 0; k < K + more; ++k) {
        writer.write(frame(k));
        if (k + 1 == 20 || k + 1 == K) writer.sync();
      }
      writer.finish();
    }
    {
      Mp4Writer writer(path, w, h);
      for (int k = 0; k < n; ++k) {
        writer.write(frame(k));
        if (k + 1 == 20) writer.sync();
      }
      writer.finish();
    }
    fs::rename(path, path.string() + ".partial");
    {
      Mp4Writer writer(path, w, h, opts("superfast", K));
      for (int k = K; k < K + more; ++k) writer.write(frame(k));
      writer.finish();
    }
    decode_checked(path, K + more);
    EXPECT_TRUE(slurp(path) == slurp(ref)) << "not the bytes of the run that was never stopped";
    fs::remove(path);
    fs::remove(ref);
  }
}

// What a user sees when the checkpoint and the folder disagree: a clear error, and the old
// .partial left exactly as it was.
TEST(Mp4Resume, RefusesWhatItCannotContinue) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "run.mp4";
  const fs::path partial = path.string() + ".partial";
  const int w = 96, h = 64;
  const auto refused = [&](const std::string& what, int ww, int hh, const Mp4Options& o, const std::string& expect) {
    SCOPED_TRACE(what);
    const std::string before = fs::exists(partial) ? slurp(partial) : "";
    try {
      Mp4Writer writer(path, ww, hh, o);
      ADD_FAILURE() << "resumed";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(partial.string()), std::string::npos) << e.what();
      std::printf("  %s: %s\n", what.c_str(), e.what());
    }
    EXPECT_TRUE((fs::exists(partial) ? slurp(partial) : "") == before) << "the old .partial changed";
    EXPECT_FALSE(fs::exists(partial.string() + ".resuming"));
    EXPECT_FALSE(fs::exists(path));
  };
  refused("no .partial", w, h, opts("superfast", 5), "is missing: cannot continue it");
  EXPECT_TRUE(fs::is_empty(dir));

  {
    Mp4Writer writer(path, w, h);
    for (int k = 0; k < 10; ++k) writer.write(smooth_pattern(w, h, 0.3 * k));
    writer.sync();
    for (int k = 10; k < 14; ++k) writer.write(smooth_pattern(w, h, 0.3 * k));
  }  // 14 frames, synced at 10
  refused("more frames than it holds", w, h, opts("superfast", 15), "holds 14 frames, the checkpoint needs 15");
  refused("another size", 128, 64, opts("superfast", 10), "it is 96x64 but the frames are 128x64");
  Mp4Options fps25 = opts("superfast", 10);
  fps25.fps = 25;
  refused("another frame rate", w, h, fps25, "frame rate is 30");
  refused("another preset", w, h, opts("ultrafast", 10), "parameter sets (SPS/PPS) differ");
  // Not where it synced: x264 put frames 10, 13, 11, 12 in that decode order (B-frames), so
  // its first 12 packets are frames 0..10 and 13. (At 7 it would resume: its first 7
  // packets happen to be frames 0..6, a self-contained prefix.)
  refused("not synced there", w, h, opts("superfast", 12), "so it was not synced at frame 12");
  fs::resize_file(partial, 20);  // not an MP4 any more
  refused("unreadable", w, h, opts("superfast", 5), "it cannot be read");
  EXPECT_THROW(Mp4Writer(path, w, h, opts("superfast", -1)), Error);
}

// A resume killed during its copy leaves `<path>.partial.resuming` beside the intact old
// .partial; the next resume overwrites it and renames it into place.
TEST(Mp4Resume, KilledResumeLeavesTheOldPartialAndIsRetried) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "run.mp4";
  const fs::path partial = path.string() + ".partial", resuming = partial.string() + ".resuming";
  const int w = 96, h = 64, K = 10;
  {
    Mp4Writer writer(path, w, h);
    for (int k = 0; k < K; ++k) writer.write(solid(w, h, k, 0));
    writer.sync();
    for (int k = K; k < 14; ++k) writer.write(solid(w, h, k, 0));
  }
  {
    std::ofstream half(resuming, std::ios::binary);
    half << std::string(5000, 'x');  // what a killed copy left
  }
  {
    Mp4Writer writer(path, w, h, opts("superfast", K));
    EXPECT_FALSE(fs::exists(resuming));
    for (int k = K; k < 16; ++k) writer.write(solid(w, h, k, 1));
    writer.finish();
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  const Checked c = decode_checked(path, 16);
  for (int k = 0; k < int(c.d.frames.size()); ++k) expect_shows(c.d.frames[std::size_t(k)], k, k < K ? 0 : 1);
}

// resume_frames = 0 is a new video: an old .partial (here of another size) is replaced.
TEST(Mp4Resume, ZeroFramesStartsANewVideo) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "run.mp4";
  {
    Mp4Writer writer(path, 64, 48);
    for (int k = 0; k < 5; ++k) writer.write(smooth_pattern(64, 48, k));
  }
  {
    Mp4Writer writer(path, 96, 64, opts("superfast", 0));
    for (int k = 0; k < 6; ++k) writer.write(smooth_pattern(96, 64, k));
    writer.finish();
  }
  const Checked c = decode_checked(path, 6);
  EXPECT_EQ(c.d.width, 96);
}

// Mp4Sink learns the size from its first frame, which for a resumed run is frame K; behind
// parallel_sinks() (AsyncSink workers) a sync waits for the queue and the encoder.
TEST(Mp4Sink, SyncsBehindAsyncWorkersAndResumes) {
  const fs::path dir = fresh_dir();
  const fs::path path = dir / "run.mp4";
  const fs::path partial = path.string() + ".partial";
  const int w = 112, h = 72, K = 16, n = 40;
  {
    std::vector<std::unique_ptr<FrameSink>> sinks;
    sinks.push_back(std::make_unique<Mp4Sink>(path, opts()));
    sinks.push_back(std::make_unique<PngSequenceSink>(dir / "frames"));
    auto out = parallel_sinks(std::move(sinks), 3);
    out->sync();  // before any frame
    for (int k = 0; k < K; ++k) out->consume(solid(w, h, k, 0), k, k / 30.0);
    out->sync();
    EXPECT_EQ(frames_in_copy(partial, dir / "k.copy"), K) << "sync() returned before the frames were on disk";
    EXPECT_TRUE(fs::exists(dir / "frames" / "frame_000015.png"));
    for (int k = K; k < 25; ++k) out->consume(solid(w, h, k, 0), k, k / 30.0);
  }  // dropped: the run stopped
  {
    Mp4Sink wrong(path, opts("superfast", K));
    EXPECT_THROW(wrong.consume(solid(w, h, 0, 1), 0, 0.0), Error) << "a resumed sink starts at frame K";
  }
  {
    Mp4Sink wrong(path, opts("superfast", K));
    EXPECT_THROW(wrong.consume(solid(w + 2, h, K, 1), K, 0.0), Error) << "another frame size";
  }
  {
    auto out = std::make_unique<AsyncSink>(std::make_unique<Mp4Sink>(path, opts("superfast", K)));
    out->sync();  // nothing consumed yet: the old .partial is still the checkpoint's prefix
    for (int k = K; k < n; ++k) out->consume(solid(w, h, k, 1), k, k / 30.0);
    out->sync();
    EXPECT_EQ(frames_in_copy(partial, dir / "n.copy"), n);
    out->finish();
  }
  const Checked c = decode_checked(path, n);
  for (int k = 0; k < int(c.d.frames.size()); ++k)
    expect_shows(c.d.frames[std::size_t(k)], k, k < K ? 0 : 1);
}

}  // namespace
}  // namespace grainflow::render
