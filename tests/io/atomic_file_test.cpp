#include "engine/io/atomic_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <sys/mount.h>
#include <cerrno>
#include <cstring>
#include <string>

#include "engine/core/error.hpp"
#include "tests/render/output_test_support.hpp"

namespace grainflow::io {
namespace {

namespace fs = std::filesystem;
using render::test::fresh_dir;
using render::test::slurp;

int entries(const fs::path& dir) {
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(AtomicFile, FinalNameAppearsOnlyAtCommit) {
  const fs::path dir = fresh_dir();
  const fs::path target = dir / "stats.csv";
  AtomicFile f(target);
  EXPECT_EQ(f.final_path(), target);
  EXPECT_EQ(f.path().parent_path(), dir) << "temporary must be in the target's directory (rename is atomic only there)";
  EXPECT_NE(f.path(), target);
  EXPECT_TRUE(fs::exists(f.path()));
  { std::ofstream(f.path()) << "time,energy\n0,1\n"; }
  EXPECT_FALSE(fs::exists(target));
  f.commit();
  EXPECT_TRUE(f.committed());
  EXPECT_EQ(slurp(target), "time,energy\n0,1\n");
  EXPECT_EQ(entries(dir), 1) << "the temporary is gone after commit";
}

TEST(AtomicFile, UncommittedIsRemovedAndOldFileKept) {
  const fs::path dir = fresh_dir();
  const fs::path target = dir / "frame.png";
  { std::ofstream(target) << "previous run"; }
  {
    AtomicFile f(target);
    std::ofstream(f.path()) << "half-written";
    EXPECT_EQ(slurp(target), "previous run");
  }  // destroyed without commit, as when an exception unwinds a writer
  EXPECT_EQ(slurp(target), "previous run");
  EXPECT_EQ(entries(dir), 1);
}

TEST(AtomicFile, CommitReplacesExistingFile) {
  const fs::path dir = fresh_dir();
  const fs::path target = dir / "out.txt";
  { std::ofstream(target) << "old"; }
  AtomicFile f(target);
  { std::ofstream(f.path()) << "new"; }
  f.commit();
  EXPECT_EQ(slurp(target), "new");
}

TEST(AtomicFile, ExplicitAbortAndMove) {
  const fs::path dir = fresh_dir();
  AtomicFile a(dir / "a.bin");
  const fs::path temp = a.path();
  AtomicFile b(std::move(a));
  EXPECT_TRUE(fs::exists(temp)) << "moving must not remove the temporary";
  b.abort();
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_THROW(b.commit(), Error);
  EXPECT_EQ(entries(dir), 0);
}

TEST(AtomicFile, TwoWritersForOneTargetGetDistinctTemporaries) {
  const fs::path dir = fresh_dir();
  AtomicFile a(dir / "x"), b(dir / "x");
  EXPECT_NE(a.path(), b.path());
}

TEST(AtomicFile, MissingDirectoryIsAnErrorNamingPathAndReason) {
  const fs::path dir = fresh_dir();
  const fs::path target = dir / "no_such_dir" / "out.mp4";
  try {
    AtomicFile f(target);
    FAIL() << "expected grainflow::Error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(target.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;
  }
}

TEST(AtomicFile, DoubleCommitIsAnError) {
  const fs::path dir = fresh_dir();
  AtomicFile f(dir / "y");
  f.commit();
  EXPECT_THROW(f.commit(), Error);
  EXPECT_TRUE(fs::exists(dir / "y"));
}

}  // namespace
}  // namespace grainflow::io

namespace grainflow::io {
namespace {

// A full disk is named as such, and the previous file stays (a small tmpfs; root only).
TEST(WriteTextAtomically, FullDiskNamesTheFileAndKeepsThePreviousOne) {
  const std::filesystem::path dir = std::filesystem::path(GRAINFLOW_TEST_OUT) / "full_disk";
  std::filesystem::create_directories(dir);
  if (::mount("tmpfs", dir.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here: " << std::strerror(errno);
  write_text_atomically(dir / "run.json", "previous\n");
  try {
    write_text_atomically(dir / "run.json", std::string(200 * 1024, 'x'));
    ADD_FAILURE() << "a 200 kB file fitted a 64 kB disk";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("space left on device"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("run.json"), std::string::npos) << e.what();
  }
  std::ifstream in(dir / "run.json");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "previous\n");
  std::size_t entries = 0;  // no temporary left beside it
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1u);
  ::umount2(dir.c_str(), MNT_DETACH);
}

}  // namespace
}  // namespace grainflow::io
