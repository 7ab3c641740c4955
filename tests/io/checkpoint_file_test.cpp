// The checkpoint container (versioned, checksummed, atomic), the archives inside it and
// the growing .partial files a resumed run continues.
#include "engine/io/checkpoint_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/partial_file.hpp"
#include "tests/render/output_test_support.hpp"

namespace grainflow::io {
namespace {

namespace fs = std::filesystem;
using render::test::fresh_dir;
using render::test::slurp;

void spit(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
// The message of the grainflow::Error `f` throws ("" when it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string payload() {
  ArchiveWriter w;
  w.tag("state");
  w.pod(3.25);
  w.array(std::vector<std::uint32_t>{1, 2, 3});
  w.string("disks");
  return w.take();
}

TEST(CheckpointFile, RoundTripsHeaderAndPayload) {
  const fs::path dir = fresh_dir();
  const CheckpointInfo info{"ed", 0x1234abcdULL, 12.5, 42, 7};
  write_checkpoint(dir / "a.gfck", info, payload());
  const Checkpoint ck = read_checkpoint(dir / "a.gfck");
  EXPECT_EQ(ck.info.engine, "ed");
  EXPECT_EQ(ck.info.scene_fingerprint, 0x1234abcdULL);
  EXPECT_EQ(ck.info.time, 12.5);
  EXPECT_EQ(ck.info.frames, 42);
  EXPECT_EQ(ck.info.sequence, 7u);
  EXPECT_EQ(ck.payload, payload());
  ArchiveReader r(ck.payload, "payload");
  r.tag("state");
  EXPECT_EQ(r.get<double>(), 3.25);
  std::vector<std::uint32_t> v;
  r.array(v);
  EXPECT_EQ(v, (std::vector<std::uint32_t>{1, 2, 3}));
  EXPECT_EQ(r.string(), "disks");
  r.expect_end();
  // Only the final name is left: the write went through a temporary.
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(CheckpointFile, DamagedFilesAreRefusedWithTheReason) {
  const fs::path dir = fresh_dir();
  write_checkpoint(dir / "a.gfck", {"dem", 1, 0.5, 3, 1}, payload());
  const std::string good = slurp(dir / "a.gfck");

  spit(dir / "cut.gfck", good.substr(0, good.size() / 2));
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "cut.gfck"); }).find("truncated"), std::string::npos);

  std::string flipped = good;
  flipped[good.size() - 20] ^= 0x40;  // inside the payload
  spit(dir / "flipped.gfck", flipped);
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "flipped.gfck"); }).find("checksum"), std::string::npos);

  std::string other_version = good;
  other_version[8] = 99;  // the u32 after the magic
  spit(dir / "version.gfck", other_version);
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "version.gfck"); }).find("format version 99"), std::string::npos);

  spit(dir / "text.gfck", "time,kT\n0,0.02\n");
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "text.gfck"); }).find("not a grainflow checkpoint"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "missing.gfck"); }).find("cannot open"), std::string::npos);
  EXPECT_NE(error_of([&] { read_checkpoint(dir); }).find("directory"), std::string::npos);
}

TEST(Archive, LengthsBeyondTheDataAreRefusedBeforeAllocating) {
  ArchiveWriter w;
  w.pod(std::uint64_t(1) << 60);  // an array "of 2^60 doubles" followed by nothing
  ArchiveReader r(w.bytes(), "state");
  std::vector<double> v;
  EXPECT_NE(error_of([&] { r.array(v); }).find("truncated or corrupt"), std::string::npos);
  EXPECT_TRUE(v.empty());
  ArchiveWriter t;
  t.tag("disks");
  ArchiveReader rt(t.bytes(), "state");
  EXPECT_NE(error_of([&] { rt.tag("bins"); }).find("expected section 'bins'"), std::string::npos);
  ArchiveReader short_read(std::string_view("abc"), "state");
  EXPECT_NE(error_of([&] { (void)short_read.get<double>(); }).find("truncated"), std::string::npos);
}

TEST(PartialFile, ResumeCutsWhatCameAfterTheCheckpoint) {
  const fs::path dir = fresh_dir();
  std::uint64_t at = 0;
  {
    PartialFile f = PartialFile::create(dir / "stats.csv");
    f.write("time,kT\n0,1\n");
    f.flush();
    at = f.size();
    f.write("1,2\n");  // after the checkpoint: a killed run leaves it, the resume drops it
  }
  EXPECT_FALSE(fs::exists(dir / "stats.csv"));
  {
    PartialFile f = PartialFile::resume(dir / "stats.csv", at);
    f.write("1,3\n");
    f.finish();
  }
  EXPECT_EQ(slurp(dir / "stats.csv"), "time,kT\n0,1\n1,3\n");
  EXPECT_FALSE(fs::exists(dir / "stats.csv.partial"));
  // A finished file (an interrupted run) is continued too.
  {
    PartialFile f = PartialFile::resume(dir / "stats.csv", at);
    f.write("1,4\n");
  }
  EXPECT_FALSE(fs::exists(dir / "stats.csv"));
  EXPECT_EQ(slurp(dir / "stats.csv.partial"), "time,kT\n0,1\n1,4\n");
  // A file shorter than the checkpoint saw does not hold what it needs.
  EXPECT_NE(error_of([&] { PartialFile::resume(dir / "stats.csv", 1000); }).find("holds"), std::string::npos);
  EXPECT_NE(error_of([&] { PartialFile::resume(dir / "none.csv", 0); }).find("neither"), std::string::npos);
}

}  // namespace
}  // namespace grainflow::io
