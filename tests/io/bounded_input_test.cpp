// Bounded inputs (issue #12): no particle file makes a reader allocate or read without
// limit. Counts are checked against a hard limit and against the file's size before memory
// is sized by them, lines are at most 1 MiB, binary data and paths that are no text file
// fail with a clear message naming file:line, and non-finite numbers are rejected where
// they would make positions, radii, velocities or the box meaningless.
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/line_reader.hpp"
#include "engine/io/particle_reader.hpp"
#include "tests/io/reader_test_support.hpp"

using namespace grainflow;
using namespace grainflow::core;
using namespace grainflow::io;
using namespace grainflow::io::test;

namespace {





// The message of the Error that reading `path` throws ("" and a test failure if none).
std::string error_of(const std::string& path) {
  try {
    read_all(path);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << path << ": no error";
  return {};
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Peak resident set size of this process in KiB (VmHWM), after resetting it to the current
// size when `reset` (writing 5 to clear_refs, Linux ≥ 4.0); -1 where /proc says nothing.
long peak_rss_kib(bool reset) {
  if (reset) std::ofstream("/proc/self/clear_refs") << "5";
  std::ifstream in("/proc/self/status");
  std::string key;
  long value;
  while (in >> key) {
    if (key == "VmHWM:" && in >> value) return value;
    in.ignore(1 << 10, '\n');
  }
  return -1;
}

// Reading `path` must fail within a second, with a message starting "path:line:" and
// containing `fragment`, while the peak RSS grows by less than 64 MiB: the claim of the
// header is checked before memory is sized by it.
void expect_fast_small_failure(const std::string& path, int line, const std::string& fragment) {
  const long before = peak_rss_kib(true);
  const auto start = std::chrono::steady_clock::now();
  const std::string msg = error_of(path);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const long after = peak_rss_kib(false);
  EXPECT_TRUE(starts_with(msg, path + ":" + std::to_string(line) + ":")) << msg;
  EXPECT_TRUE(contains(msg, fragment)) << msg;
  EXPECT_LT(seconds, 1.0) << msg;
  if (before > 0 && after > 0) {
    EXPECT_LT(after - before, 64 * 1024) << "peak RSS grew by " << after - before << " KiB";
  }
}

const std::string kDumpHead = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n";
const std::string kBox = "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n";

// A pipe whose read end is opened by path (/dev/fd/N, as `render <(cmd)` passes it) while
// a thread writes `text` into it: a stream of unknown size.
class PipeInput {
public:
  explicit PipeInput(std::string text) {
    if (::pipe(fds_) != 0) throw std::runtime_error("pipe");
    writer_ = std::thread([this, text = std::move(text)] {
      // A reader that stops early closes the pipe: the write then fails (EPIPE) instead of
      // SIGPIPE ending the test program.
      sigset_t pipe_signal;
      sigemptyset(&pipe_signal);
      sigaddset(&pipe_signal, SIGPIPE);
      pthread_sigmask(SIG_BLOCK, &pipe_signal, nullptr);
      std::size_t done = 0;
      while (done < text.size()) {
        const ssize_t n = ::write(fds_[1], text.data() + done, text.size() - done);
        if (n <= 0) break;  // the reader stopped early (EPIPE)
        done += static_cast<std::size_t>(n);
      }
      ::close(fds_[1]);
    });
  }
  ~PipeInput() {
    ::close(fds_[0]);  // a writer still blocked gets EPIPE
    writer_.join();
  }
  std::string path() const { return "/dev/fd/" + std::to_string(fds_[0]); }

private:
  int fds_[2];
  std::thread writer_;
};

// A frame of `n` particles, "id type x y z" (x = the id, so order is checkable).
std::string dump_frame(int n) {
  std::ostringstream s;
  s << kDumpHead << n << "\n" << kBox << "ITEM: ATOMS id type x y z\n";
  for (int i = 1; i <= n; ++i) s << i << " 1 " << i << " 0.5 0.25\n";
  return s.str();
}

}  // namespace

// --- Counts -----------------------------------------------------------------------------

TEST(BoundedCounts, XyzClaimBeyondTheHardLimitFailsAtOnce) {
  expect_fast_small_failure(data("malformed/claims_1e12_atoms.xyz"), 1,
                            "the header claims 1000000000000 particles, more than the limit of 1000000000");
}

TEST(BoundedCounts, LammpsClaimBeyondTheHardLimitFailsAtOnce) {
  const std::string path = write_temp("claims_1e12.lammpstrj", kDumpHead + "1000000000000\n" + kBox +
                                                                    "ITEM: ATOMS id type x y z\n1 1 0 0 0\n");
  expect_fast_small_failure(path, 4, "the header claims 1000000000000 particles, more than the limit of 1000000000");
}

TEST(BoundedCounts, LammpsClaimBeyondTheFileSizeFailsAtOnce) {
  // 196 bytes claiming 2×10^8 atoms: the readers used to allocate ~6 GB for it.
  expect_fast_small_failure(data("malformed/claims_200M_atoms.lammpstrj"), 4,
                            "the header claims 200000000 particles but the file holds at most 8 (80 bytes left after "
                            "line 9; a particle line of 5 columns takes at least 10 bytes)");
}

TEST(BoundedCounts, XyzClaimBeyondTheFileSizeFailsAtOnce) {
  const std::string path =
      write_temp("claims_200M.xyz", "200000000\nProperties=species:S:1:pos:R:3:radius:R:1\nH 0 0 0 0.5\n");
  expect_fast_small_failure(path, 1, "the header claims 200000000 particles but the file holds at most 1 (12 bytes left");
  // Plain XYZ: at least 4 columns (species x y z) per line.
  const std::string plain = write_temp("claims_200M_plain.xyz", "200000000\nplain\nH 0 0 0\n");
  expect_fast_small_failure(plain, 1, "holds at most 1 (8 bytes left after line 2; a particle line of 4 columns");
}

TEST(BoundedCounts, ShortfallsTheFileCouldHoldAreReportedWhereItEnds) {
  // 2 particles of 5 columns need 19 bytes, 12 are left: the frame is truncated, and the
  // reader says so where the file ends rather than at the header.
  const std::string path = write_temp("short2.xyz", "2\nProperties=species:S:1:pos:R:3:radius:R:1\nH 0 0 0 0.5\n");
  const std::string msg = error_of(path);
  EXPECT_TRUE(starts_with(msg, path + ":3: file ends after 1 of the 2 particle lines")) << msg;
}

TEST(BoundedCounts, StreamOfUnknownSizeGrowsWithItsLinesNotItsHeader) {
  // Through a pipe the size is unknown: the header's 2×10^8 is not trusted, the frame is
  // sized modestly and the truncation is found after the lines that are there.
  PipeInput pipe(kDumpHead + "200000000\n" + kBox + "ITEM: ATOMS id type x y z\n1 1 0 0 0\n2 1 1 0 0\n");
  const long before = peak_rss_kib(true);
  const std::string msg = error_of(pipe.path());
  const long after = peak_rss_kib(false);
  EXPECT_TRUE(starts_with(msg, pipe.path() + ":11: file ends after 2 of the 200000000 atoms announced on line 4"))
      << msg;
  if (before > 0 && after > 0) {
    EXPECT_LT(after - before, 64 * 1024) << "peak RSS grew by " << after - before << " KiB";
  }
}

TEST(BoundedCounts, LargeFrameThroughAPipeReadsLikeTheFile) {
  // 200000 particles: more than a stream's first reservation, so the frame grows while it
  // is read; the result must be that of the same file read from disk.
  const std::string text = dump_frame(200000) + dump_frame(3);
  const std::string file = write_temp("large_frame.lammpstrj", text);
  const auto from_file = read_all(file);
  PipeInput pipe(text);
  const auto from_pipe = read_all(pipe.path());
  ASSERT_EQ(from_pipe.size(), 2u);
  ASSERT_EQ(from_file.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const auto& a = from_file[k];
    const auto& b = from_pipe[k];
    ASSERT_EQ(b.size(), a.size());
    EXPECT_EQ(b.position, a.position);
    EXPECT_EQ(b.radius, a.radius);
    EXPECT_EQ(b.id, a.id);
    EXPECT_EQ(b.type, a.type);
    b.check_consistent("pipe frame");
  }
  EXPECT_EQ(from_pipe[0].size(), 200000u);
  EXPECT_EQ(from_pipe[0].position[199999].x(), 200000.0);
  EXPECT_EQ(from_pipe[1].size(), 3u);
}

TEST(BoundedCounts, XyzThroughAPipeKeepsItsExtraAndVelocityColumns) {
  const std::string text = "2\nProperties=species:S:1:pos:R:3:velo:R:3:mass:R:1\nH 0 0 0 1 2 3 7\nO 1 0 0 4 5 6 8\n";
  PipeInput pipe(text);
  const auto frames = read_all(pipe.path());
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].velocity[1], Vec3(4, 5, 6));
  EXPECT_EQ((*frames[0].column("mass"))[1], 8.0);
  frames[0].check_consistent("pipe frame");
}

// --- Lines ------------------------------------------------------------------------------

TEST(BoundedLines, DevZeroIsBinaryData) {
  const auto start = std::chrono::steady_clock::now();
  try {
    open_particle_file("/dev/zero");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "/dev/zero:1: binary data (a NUL byte at byte 1 of the line): not a text particle file");
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

TEST(BoundedLines, NulBytesLaterInAFileNameTheirLine) {
  std::string text = dump_frame(2);
  text.insert(text.size() - 3, 1, '\0');  // inside the last atom line, line 11
  const std::string path = write_temp("nul.lammpstrj", text);
  const std::string msg = error_of(path);
  EXPECT_TRUE(starts_with(msg, path + ":11: binary data (a NUL byte at byte ")) << msg;
}

TEST(BoundedLines, TwoMebibyteLineIsRefused) {
  const std::string path = write_temp("long_line.xyz", std::string(2 << 20, '7') + "\n");
  const std::string msg = error_of(path);
  EXPECT_TRUE(starts_with(msg, path + ":1: line longer than 1 MiB (1048576 bytes)")) << msg;
  // A file without any line break stops the same way, and so does a long line later on.
  const std::string no_break = write_temp("no_break.xyz", "1\n" + std::string(3 << 20, 'x'));
  EXPECT_TRUE(starts_with(error_of(no_break), no_break + ":2: line longer than 1 MiB")) << error_of(no_break);
  const std::string later = write_temp("long_atom_line.lammpstrj", kDumpHead + "2\n" + kBox + "ITEM: ATOMS id type x y z\n" +
                                                                      "1 1 0 0 0\n" + std::string(kMaxLineBytes + 1, '1') + "\n");
  EXPECT_TRUE(starts_with(error_of(later), later + ":11: line longer than 1 MiB")) << error_of(later);
}

TEST(BoundedLines, LineOfExactlyTheLimitIsRead) {
  // The comment line of an XYZ frame is free text: 1 MiB of it is still a line.
  const std::string path = write_temp("limit_line.xyz", "1\n" + std::string(kMaxLineBytes, 'c') + "\nH 0 0 1\n");
  const auto frames = read_all(path);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].position[0], Vec3(0, 0, 1));
  const std::string over = write_temp("over_limit_line.xyz", "1\n" + std::string(kMaxLineBytes + 1, 'c') + "\nH 0 0 1\n");
  EXPECT_TRUE(starts_with(error_of(over), over + ":2: line longer than 1 MiB")) << error_of(over);
}

TEST(BoundedLines, LastLineWithoutNewlineAndManyBuffersOfLines) {
  // Frames spanning several read buffers (lines cut at buffer boundaries), the last line
  // without its '\n'.
  std::string text;
  for (int k = 0; k < 3; ++k) text += dump_frame(60000);
  text += dump_frame(2);
  text.pop_back();
  const auto frames = read_all(write_temp("many_buffers.lammpstrj", text));
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[2].position[59999].x(), 60000.0);
  EXPECT_EQ(frames[3].position[1], Vec3(2, 0.5, 0.25));
}

TEST(BoundedLines, GzipIsStillNamedAsSuch) {
  // Real gzip data holds NUL bytes: the probe must name the format, not "binary data".
  const std::string path = write_temp("real.gz", std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03", 10) + "xyz\n");
  try {
    open_particle_file(path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": gzip-compressed; decompress it first (gunzip)");
  }
}

TEST(BoundedLines, MessagesEscapeRawBytesAndCutLongTokens) {
  EXPECT_EQ(printable("abc"), "abc");
  EXPECT_EQ(printable("a\x1b[31mb"), "a\\x1b[31mb");
  EXPECT_EQ(printable("\xff\x01"), "\\xff\\x01");
  EXPECT_EQ(printable(std::string(50, 'x')), std::string(37, 'x') + "...");
  // (std::string::append, not "'" + ...: GCC 12 -Wrestrict false positive.)
  EXPECT_EQ(quote_token(std::string(41, 'y')), std::string("'").append(37, 'y').append("...'"));
  EXPECT_EQ(quote_token(std::string(40, 'y')), std::string("'").append(40, 'y').append("'"));
  // An escape is never cut in half.
  EXPECT_EQ(printable(std::string(35, 'x') + "\x07\x07"), std::string(35, 'x') + "...");
  const std::string path = write_temp("escape.lammpstrj", kDumpHead + "1\n" + kBox +
                                                             "ITEM: ATOMS id type x y z\n1 1 \x1b]0;pwned\x07 0 0\n");
  const std::string msg = error_of(path);
  EXPECT_TRUE(contains(msg, "column 3 (x): expected a finite number, got '\\x1b]0;pwned\\x07'")) << msg;
  EXPECT_FALSE(contains(msg, "\x1b")) << msg;
  const std::string names = write_temp("escape_names.lammpstrj", kDumpHead + "1\n" + kBox +
                                                                    "ITEM: ATOMS id type x y z m\x1b\n1 1 0 0 0 q\n");
  const std::string msg2 = error_of(names);
  EXPECT_TRUE(contains(msg2, "column 6 (m\\x1b): expected a number, got 'q'")) << msg2;
}

// --- Paths that are no text file ---------------------------------------------------------

TEST(BoundedPaths, DirectoryIsNamedAsSuch) {
  const std::string dir = out_path("a_directory.xyz");
  std::filesystem::create_directories(dir);
  try {
    open_particle_file(dir);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "'" + dir + "' is a directory, not a particle file");
  }
}

TEST(BoundedPaths, MissingFileSaysWhy) {
  const std::string path = out_path("no_such_dir/none.xyz");
  try {
    open_particle_file(path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot open for reading (No such file or directory)");
  }
}

TEST(BoundedPaths, NamedFifoIsReadOnceAsAStream) {
  // The format probe and the reader share one open file, so a FIFO's first lines are not
  // lost to the probe.
  const std::string path = out_path("particles.fifo");
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(path) << "1\nplain\nH 1 2 3\n1\nplain\nH 4 5 6\n"; });
  const auto frames = read_all(path);
  writer.join();
  std::filesystem::remove(path);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].position[0], Vec3(4, 5, 6));
}

// --- Non-finite numbers -----------------------------------------------------------------

TEST(BoundedNumbers, NonFiniteCoordinatesNameTheColumn) {
  for (const std::string bad : {"nan", "-inf", "1e999", "NaN"}) {
    const std::string dump = write_temp("nonfinite.lammpstrj", kDumpHead + "1\n" + kBox +
                                                                  "ITEM: ATOMS id type x y z\n1 1 0 " + bad + " 0\n");
    std::string msg = error_of(dump);
    EXPECT_TRUE(starts_with(msg, dump + ":10: column 4 (y): expected a finite number, got '" + bad + "'")) << msg;

    const std::string ext = write_temp("nonfinite.xyz", "1\nProperties=species:S:1:pos:R:3\nH 0 0 " + bad + "\n");
    msg = error_of(ext);
    EXPECT_TRUE(starts_with(msg, ext + ":3: column 4 (pos): expected a finite number, got '" + bad + "'")) << msg;

    const std::string plain = write_temp("nonfinite_plain.xyz", "1\nplain\nH " + bad + " 0 0\n");
    msg = error_of(plain);
    EXPECT_TRUE(starts_with(msg, plain + ":3: position x of particle 1: expected a finite number, got '" + bad + "'"))
        << msg;
  }
}

TEST(BoundedNumbers, NonFiniteRadiiAndVelocitiesNameTheColumn) {
  const std::string dump = write_temp("nonfinite_v.lammpstrj", kDumpHead + "1\n" + kBox +
                                                                  "ITEM: ATOMS id type x y z vx vy vz radius\n1 1 0 0 0 0 inf 0 0.5\n");
  std::string msg = error_of(dump);
  EXPECT_TRUE(starts_with(msg, dump + ":10: column 7 (vy): expected a finite number, got 'inf'")) << msg;
  const std::string rad = write_temp("nonfinite_r.lammpstrj", kDumpHead + "1\n" + kBox +
                                                                 "ITEM: ATOMS id type x y z radius\n1 1 0 0 0 nan\n");
  msg = error_of(rad);
  EXPECT_TRUE(starts_with(msg, rad + ":10: column 6 (radius): expected a finite number, got 'nan'")) << msg;
  const std::string xyz = write_temp("nonfinite_r.xyz", "1\nProperties=species:S:1:pos:R:3:radius:R:1\nH 0 0 0 1e999\n");
  msg = error_of(xyz);
  EXPECT_TRUE(starts_with(msg, xyz + ":3: column 5 (radius): expected a finite number, got '1e999'")) << msg;
}

TEST(BoundedNumbers, NonFiniteBoxBoundsNameTheColumn) {
  const auto dump_with_box = [](const std::string& box_lines) {
    return kDumpHead + "1\n" + box_lines + "ITEM: ATOMS id type x y z\n1 1 0 0 0\n";
  };
  std::string path = write_temp("box_nan.lammpstrj", dump_with_box("ITEM: BOX BOUNDS pp pp pp\n0 1\nnan 1\n0 1\n"));
  std::string msg = error_of(path);
  EXPECT_EQ(msg, path + ":7: column 1 (ylo) of the box bounds: expected a finite number, got 'nan'");
  path = write_temp("box_big.lammpstrj", dump_with_box("ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1e999\n"));
  msg = error_of(path);
  EXPECT_EQ(msg, path + ":8: column 2 (zhi) of the box bounds: expected a finite number, got '1e999'");
  path = write_temp("box_tilt.lammpstrj",
                    dump_with_box("ITEM: BOX BOUNDS xy xz yz pp pp pp\n0 1 inf\n0 1 0\n0 1 0\n"));
  msg = error_of(path);
  EXPECT_EQ(msg, path + ":6: column 3 (xy) of the box bounds: expected a finite number, got 'inf'");

  path = write_temp("lattice_nan.xyz", "1\nLattice=\"1 0 0 0 nan 0 0 0 1\" Properties=species:S:1:pos:R:3\nH 0 0 0\n");
  msg = error_of(path);
  EXPECT_TRUE(starts_with(msg, path + ":2: Lattice=\"1 0 0 0 nan 0 0 0 1\": 'nan' is not a finite number")) << msg;
  path = write_temp("origin_big.xyz",
                    "1\nLattice=\"1 0 0 0 1 0 0 0 1\" Origin=\"0 1e999 0\" Properties=species:S:1:pos:R:3\nH 0 0 0\n");
  msg = error_of(path);
  EXPECT_TRUE(starts_with(msg, path + ":2: Origin=\"0 1e999 0\": '1e999' is not a finite number")) << msg;
  path = write_temp("lattice_sum.xyz",
                    "1\nLattice=\"1e308 0 0 1e308 1 0 0 0 1\" Properties=species:S:1:pos:R:3\nH 0 0 0\n");
  msg = error_of(path);
  EXPECT_TRUE(starts_with(msg, path + ":2: Lattice and Origin give a box whose corners are not finite")) << msg;
}

TEST(BoundedNumbers, ExtraColumnsMayStillHoldNan) {
  // LAMMPS writes nan for computes that are undefined for an atom: such extra columns are
  // data, not damage (valid-file behaviour kept).
  const std::string path = write_temp("extra_nan.lammpstrj", kDumpHead + "1\n" + kBox +
                                                                "ITEM: ATOMS id type x y z c_ke\n1 1 0 0 0 nan\n");
  const auto frames = read_all(path);
  EXPECT_TRUE(std::isnan((*frames.at(0).column("c_ke"))[0]));
}
