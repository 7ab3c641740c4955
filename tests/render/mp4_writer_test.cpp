#include "render/output/mp4_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/output/mp4_sink.hpp"
#include "mp4_test_support.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

namespace fs = std::filesystem;
using test::Decoded;
using test::decodable_frames;
using test::decode;
using test::ffprobe;
using test::fresh_dir;
using test::psnr_rgb;
using test::slurp;
using test::smooth_pattern;

// The creation and modification times of every mvhd, tkhd and mdhd box (version 0 or 1),
// which QuickTime defines as seconds since 1904: a muxer that reads the clock puts it here.
std::vector<std::uint64_t> box_times(const std::string& bytes) {
  std::vector<std::uint64_t> t;
  for (const char* box : {"mvhd", "tkhd", "mdhd"})
    for (auto at = bytes.find(box); at != std::string::npos; at = bytes.find(box, at + 4)) {
      const auto be = [&](std::size_t off, int n) {
        std::uint64_t v = 0;
        for (int i = 0; i < n; ++i) v = v << 8 | std::uint8_t(bytes.at(off + i));
        return v;
      };
      const std::size_t body = at + 4;
      const int size = bytes.at(body) == 1 ? 8 : 4;  // version 1 has 64-bit times
      t.push_back(be(body + 4, size));
      t.push_back(be(body + 4 + size, size));
    }
  return t;
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
    EXPECT_TRUE(fs::exists(writer.partial_path())) << "the video is in the .partial while encoding";
    EXPECT_EQ(writer.partial_path(), fs::path(path.string() + ".partial"));
    writer.finish();
    EXPECT_EQ(writer.frames_written(), n);
    EXPECT_EQ(writer.frames_on_disk(), n);
  }
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EQ(std::distance(fs::directory_iterator(path.parent_path()), fs::directory_iterator()), 1)
      << "the .partial and the temporary of the standard copy are gone";
  const Decoded d = decode(path);
  EXPECT_EQ(d.codec, "h264");
  EXPECT_EQ(d.width, w);
  EXPECT_EQ(d.height, h);
  EXPECT_EQ(d.pix_fmt, AV_PIX_FMT_YUV420P);
  ASSERT_EQ(int(d.frames.size()), n);
  EXPECT_EQ(d.nb_frames_field, n);
  EXPECT_NEAR(d.duration_s, double(n) / fps, 0.5 / fps) << "every frame, the last included, lasts 1/fps";
  EXPECT_EQ(d.start_s, 0.0) << "frame 0 is shown at time 0 (the B-frame delay is in the edit list)";
  for (int k : {0, 10, n - 1}) {
    const double p = psnr_rgb(src[k], d.frames[k]);
    EXPECT_GT(p, 35.0) << "frame " << k;
  }
  // Frames come out in order: frame 10 matches source 10 much better than source 30.
  EXPECT_GT(psnr_rgb(src[10], d.frames[10]), psnr_rgb(src[30], d.frames[10]) + 5.0);
}

// Isolated 1-pixel dots of saturated colour on black, as a dense disk panel has: 4:2:0 shares
// one chroma sample among 2x2 pixels and smears them; 4:4:4 keeps every pixel's colour.
TEST(Mp4Writer, ChromaFourFourFourKeepsOnePixelColours) {
  const int w = 64, h = 48;
  Image dots(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = dots.pixel(x, y);
      const bool on = (x % 3 == 0) && (y % 3 == 0);
      const int hue = (x / 3 + y / 3) % 3;
      p[0] = on && hue == 0 ? 230 : 0;
      p[1] = on && hue == 1 ? 230 : 0;
      p[2] = on && hue == 2 ? 230 : 0;
      p[3] = 255;
    }
  double quality[2] = {0, 0};
  for (bool full : {false, true}) {
    const fs::path path = fresh_dir() / (full ? "c444.mp4" : "c420.mp4");
    Mp4Options opt{30, 0, "veryfast", 1};
    opt.chroma_444 = full;
    Mp4Writer writer(path, w, h, opt);
    for (int k = 0; k < 3; ++k) writer.write(dots);
    writer.finish();
    const Decoded d = decode(path);
    EXPECT_EQ(d.pix_fmt, full ? AV_PIX_FMT_YUV444P : AV_PIX_FMT_YUV420P);
    ASSERT_EQ(d.frames.size(), 3u);
    quality[full] = psnr_rgb(dots, d.frames[1]);
  }
  std::printf("1-pixel dots, crf 0: 4:2:0 %.1f dB, 4:4:4 %.1f dB\n", quality[0], quality[1]);
  // Measured: 4:2:0 17 dB (chroma smeared over 2x2), 4:4:4 at crf 0 exact for these
  // colours (PSNR at the 1e-12 floor); 40 dB leaves room for YCbCr rounding of others.
  EXPECT_LT(quality[0], 30.0);
  EXPECT_GT(quality[1], 40.0);
  EXPECT_GT(quality[1], quality[0] + 12.0);
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

TEST(Mp4Writer, UnfinishedWriterKeepsItsFramesInThePartial) {
  const fs::path dir = fresh_dir();
  {
    Mp4Writer writer(dir / "stopped.mp4", 64, 48);
    for (int k = 0; k < 10; ++k) writer.write(smooth_pattern(64, 48, k));
    EXPECT_LT(writer.frames_on_disk(), 10) << "some frames are still inside x264";
  }
  // Destroyed without finish() (an exception elsewhere stopped the run): the frames x264
  // still held are flushed, so the .partial holds all ten; the final name stays free.
  EXPECT_FALSE(fs::exists(dir / "stopped.mp4"));
  ASSERT_TRUE(fs::exists(dir / "stopped.mp4.partial"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  EXPECT_EQ(decode(dir / "stopped.mp4.partial").frames.size(), 10u);
}

TEST(Mp4Writer, WriterWithoutFramesLeavesNoFile) {
  const fs::path dir = fresh_dir();
  { Mp4Writer writer(dir / "empty.mp4", 64, 48); }
  EXPECT_TRUE(fs::is_empty(dir)) << "a .partial without a frame is no video";
}

// The fault #12 is about: the process dies (SIGKILL here; SIGHUP, SIGSEGV or the OOM
// killer end it the same way, without unwinding) in the middle of a video.
TEST(Mp4Writer, KilledEncoderLeavesAPlayablePartial) {
  const fs::path path = fresh_dir() / "killed.mp4";
  const int w = 160, h = 96, n = 40, signal_after = 25;
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // The child only encodes; any failure shows as an exit code instead of a gtest result.
    close(fds[0]);
    try {
      Mp4Writer writer(path, w, h);  // the default options, as scenes use them
      for (int k = 0; k < n; ++k) {
        writer.write(smooth_pattern(w, h, 0.2 * k));
        if (k + 1 == signal_after) {
          const std::int64_t counts[2] = {writer.frames_written(), writer.frames_on_disk()};
          if (write(fds[1], counts, sizeof counts) != ssize_t(sizeof counts)) _exit(3);
        }
      }
      for (;;) pause();  // never finish(): the parent kills this process
    } catch (...) {
      _exit(2);
    }
  }
  close(fds[1]);
  std::int64_t counts[2] = {0, 0};
  const ssize_t got = read(fds[0], counts, sizeof counts);  // blocks until frame 25 is in
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  close(fds[0]);
  ASSERT_EQ(got, ssize_t(sizeof counts)) << "the child failed, wait status " << status;
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "wait status " << status;

  const std::int64_t consumed = counts[0], on_disk = counts[1];
  EXPECT_EQ(consumed, signal_after);
  // Only what x264 holds is missing at any moment: with the default options (superfast:
  // 3 B-frames and their lookahead; 2 frame threads) 9 frames, measured; x264's frame
  // pipeline is synchronous, so the count does not depend on timing.
  const std::int64_t default_encoder_delay = 9;
  EXPECT_GE(on_disk, consumed - default_encoder_delay) << "frames inside the encoder";
  EXPECT_FALSE(fs::exists(path)) << "an unfinished video never takes the final name";
  const fs::path partial = path.string() + ".partial";
  ASSERT_TRUE(fs::exists(partial));
  const std::int64_t decoded = decodable_frames(partial);
  EXPECT_GE(decoded, on_disk) << "every frame handed to the kernel before the kill decodes";
  EXPECT_GE(decoded, signal_after - default_encoder_delay);
  EXPECT_LE(decoded, n);
  const std::string probed =
      ffprobe("-count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0", partial);
  if (!probed.empty()) {
    EXPECT_GE(std::atoll(probed.c_str()), on_disk) << "ffprobe: " << probed;
  }
  std::printf("  SIGKILL after %lld frames consumed: %lld were on disk at the signal; the .partial "
              "(%lld bytes) decodes %lld frames (ffprobe nb_read_frames: %s)\n",
              static_cast<long long>(consumed), static_cast<long long>(on_disk),
              static_cast<long long>(fs::file_size(partial)), static_cast<long long>(decoded),
              probed.empty() ? "not installed" : probed.c_str());

  // The frames are the right ones, in order.
  const Decoded d = decode(partial);
  ASSERT_GE(std::int64_t(d.frames.size()), on_disk);
  EXPECT_EQ(d.width, w);
  for (std::int64_t k : {std::int64_t(0), on_disk - 1})
    EXPECT_GT(psnr_rgb(smooth_pattern(w, h, 0.2 * double(k)), d.frames[std::size_t(k)]), 35.0) << "frame " << k;
}

TEST(Mp4Writer, FinishedFileIsAStandardMp4WithItsFrameCount) {
  const fs::path path = fresh_dir() / "done.mp4";
  const int n = 37, fps = 24;
  {
    Mp4Writer writer(path, 96, 64, Mp4Options{fps, 23, "superfast", 2});
    for (int k = 0; k < n; ++k) writer.write(smooth_pattern(96, 64, 0.3 * k));
    writer.finish();
  }
  const std::string bytes = slurp(path);
  EXPECT_EQ(bytes.find("moof"), std::string::npos) << "not fragmented: one index for the whole file";
  EXPECT_EQ(bytes.find("mvex"), std::string::npos);
  EXPECT_LT(bytes.find("moov"), bytes.find("mdat"));
  const Decoded d = decode(path);
  EXPECT_EQ(int(d.frames.size()), n);
  EXPECT_EQ(d.nb_frames_field, n);
  EXPECT_NEAR(d.duration_s, double(n) / fps, 0.5 / fps);
  EXPECT_EQ(d.start_s, 0.0);
  const std::string probed = ffprobe("-show_entries stream=nb_frames,duration,start_time -of csv=p=0", path);
  if (!probed.empty()) {
    char expect[64];
    std::snprintf(expect, sizeof expect, "0.000000,%.6f,%d", double(n) / fps, n);
    EXPECT_EQ(probed, expect) << "ffprobe start_time,duration,nb_frames";
  }
}

TEST(Mp4Writer, SameFramesGiveTheSameBytesAndNoClockTimes) {
  const fs::path dir = fresh_dir();
  std::string partials[2];
  for (const char* name : {"a.mp4", "b.mp4"}) {
    Mp4Writer writer(dir / name, 80, 48);
    for (int k = 0; k < 12; ++k) writer.write(smooth_pattern(80, 48, 0.4 * k));
    // The fragments on disk so far: the bytes a kill would leave.
    partials[name[0] - 'a'] = slurp(writer.partial_path()).substr(0, 2000);
    writer.finish();
  }
  const std::string a = slurp(dir / "a.mp4"), b = slurp(dir / "b.mp4");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "same frames and options, different bytes";
  EXPECT_TRUE(partials[0] == partials[1]);
  for (const std::string* bytes : {&a, static_cast<const std::string*>(&partials[0])}) {
    const auto times = box_times(*bytes);
    EXPECT_FALSE(times.empty());
    for (std::uint64_t t : times) EXPECT_EQ(t, 0u) << "a creation/modification time from the clock";
  }
  EXPECT_EQ(a.find("Lavf"), std::string::npos) << "no library version in the file";
}

// A full disk with the project's wording, found by users searching for it, naming the
// file, and reported the same way at every later call: the first error is the cause.
TEST(Mp4Writer, FullDiskAtTheStartNamesTheFile) {
  const fs::path dir = fresh_dir();
  // /dev/full fails every write with ENOSPC; the .partial is pointed at it.
  std::error_code ec;
  fs::create_symlink("/dev/full", dir / "full.mp4.partial", ec);
  if (ec || !fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  try {
    Mp4Writer writer(dir / "full.mp4", 64, 48);
    FAIL() << "writing to a full disk succeeded";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("no space left on device"), std::string::npos) << msg;
    EXPECT_NE(msg.find((dir / "full.mp4.partial").string()), std::string::npos) << msg;
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing playable was written, so nothing is left";
}

// A small tmpfs as a disk that fills up during the encode (root only; skipped otherwise).
class SmallDisk {
public:
  SmallDisk(const fs::path& dir, std::size_t bytes) : dir_(dir) {
    fs::create_directories(dir_);
    const std::string opts = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", dir_.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, opts.c_str()) == 0) mounted_ = true;
    else reason_ = std::strerror(errno);
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }
  const std::string& reason() const { return reason_; }

private:
  fs::path dir_;
  bool mounted_ = false;
  std::string reason_;
};

TEST(Mp4Writer, DiskFullMidwayKeepsTheFramesWrittenAndReportsTheFirstError) {
  const fs::path dir = fresh_dir() / "disk";
  SmallDisk disk(dir, 200 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a 200 KB tmpfs (" << disk.reason() << ")";
  const fs::path path = dir / "run.mp4";
  // Noise does not compress: ~30 KB a frame, so the disk is full after a few frames.
  std::optional<std::string> first;
  std::int64_t on_disk = 0;
  {
    Mp4Writer writer(path, 128, 128, Mp4Options{30, 20, "ultrafast", 1});
    for (int k = 0; k < 60 && !first; ++k) {
      try {
        writer.write(test::random_image(128, 128, k));
      } catch (const Error& e) {
        first = e.what();
      }
    }
    ASSERT_TRUE(first) << "200 KB held 60 noise frames";
    on_disk = writer.frames_on_disk();
    EXPECT_NE(first->find("no space left on device"), std::string::npos) << *first;
    EXPECT_NE(first->find(writer.partial_path().string()), std::string::npos) << *first;
    EXPECT_NE(first->find("first " + std::to_string(on_disk) + " frames remain playable"), std::string::npos)
        << *first;
    for (int attempt = 0; attempt < 2; ++attempt) {
      try {
        if (attempt == 0) writer.write(test::random_image(128, 128, 99));
        else writer.finish();
        ADD_FAILURE() << "a writer that failed went on";
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), *first) << "a later call reports the first error";
      }
    }
  }
  EXPECT_GT(on_disk, 0);
  EXPECT_FALSE(fs::exists(path)) << "a failed video never takes the final name";
  ASSERT_TRUE(fs::exists(path.string() + ".partial")) << "the frames that fit are kept";
  EXPECT_GE(decodable_frames(path.string() + ".partial"), on_disk);
  std::printf("  200 KB disk: %s\n", first->c_str());
}

TEST(Mp4Writer, DiskFullAtFinishKeepsTheCompletePartial) {
  const fs::path root = fresh_dir();
  const auto encode = [](const fs::path& path) {
    Mp4Writer writer(path, 128, 128, Mp4Options{30, 20, "ultrafast", 1});
    for (int k = 0; k < 8; ++k) writer.write(test::random_image(128, 128, k));
    writer.finish();
  };
  // The same frames give the same bytes, so a trial run tells the .partial's size.
  {
    Mp4Writer writer(root / "trial.mp4", 128, 128, Mp4Options{30, 20, "ultrafast", 1});
    for (int k = 0; k < 8; ++k) writer.write(test::random_image(128, 128, k));
  }  // destroyed unfinished: the complete .partial stays
  const std::uintmax_t partial_size = fs::file_size(root / "trial.mp4.partial");
  // Room for the .partial but not for the standard copy beside it.
  const fs::path dir = root / "disk";
  SmallDisk disk(dir, std::size_t(partial_size * 3 / 2) / 4096 * 4096);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs (" << disk.reason() << ")";
  try {
    encode(dir / "run.mp4");
    FAIL() << "the standard copy fitted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("no space left on device"), std::string::npos) << msg;
    EXPECT_NE(msg.find("the complete video (fragmented MP4, 8 frames) stays in '" + (dir / "run.mp4.partial").string()),
              std::string::npos)
        << msg;
  }
  EXPECT_FALSE(fs::exists(dir / "run.mp4"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "only the .partial";
  EXPECT_EQ(decodable_frames(dir / "run.mp4.partial"), 8);
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

TEST(Mp4Sink, ReportsTheFirstErrorAgain) {
  const fs::path dir = fresh_dir() / "gone";
  fs::create_directories(dir);
  Mp4Sink sink(dir / "x.mp4", Mp4Options{25, 23, "ultrafast", 1});
  fs::remove_all(dir);  // the folder disappears after the checks at construction
  std::string first;
  try {
    sink.consume(smooth_pattern(32, 32, 0), 0, 0.0);
  } catch (const Error& e) {
    first = e.what();
  }
  ASSERT_NE(first.find("x.mp4.partial"), std::string::npos) << first;
  fs::create_directories(dir);  // even when the cause is gone: the video lacks its frame 0
  for (int attempt = 0; attempt < 2; ++attempt) {
    try {
      if (attempt == 0) sink.consume(smooth_pattern(32, 32, 1), 1, 0.04);
      else sink.finish();
      ADD_FAILURE() << "a failed sink went on";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), first);
    }
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace grainflow::render
