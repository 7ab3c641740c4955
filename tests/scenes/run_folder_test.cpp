// Run folder creation rules, run.json content and the JSON writer's escaping.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "engine/core/error.hpp"
#include "scenes/src/outputs/json_writer.hpp"
#include "scenes/src/outputs/run_output.hpp"
#include "scenes/src/run/run_folder.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"

using namespace grainflow::scenes;
namespace fs = std::filesystem;

namespace {

fs::path fresh(const std::string& name) {
  const fs::path d = fs::path(GRAINFLOW_TEST_OUT) / "run_folder" / name;
  fs::remove_all(d);
  return d;
}

void touch(const fs::path& p, const std::string& text = "x") { std::ofstream(p) << text; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::string error_of(const fs::path& dir, RunFolderMode mode) {
  try {
    RunFolder::open(dir, mode);
  } catch (const grainflow::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RunFolder, CreatesFolderAndFrames) {
  const fs::path d = fresh("new") / "nested";
  const RunFolder f = RunFolder::open(d, RunFolderMode::Fresh);
  EXPECT_TRUE(fs::is_directory(d / "frames"));
  EXPECT_EQ(f.file("stats.csv"), d / "stats.csv");
  EXPECT_EQ(f.frames_dir(), d / "frames");
  // Only frames/, the (empty) file list and the lock are left: the write probe is removed.
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++n;
  EXPECT_EQ(n, 3u);
  EXPECT_TRUE(fs::exists(d / RunFolder::kLock));
  EXPECT_TRUE(fs::exists(d / RunFolder::kManifest));
  // An existing empty folder is fine.
  const fs::path e = fresh("empty");
  fs::create_directories(e);
  EXPECT_NO_THROW(RunFolder::open(e, RunFolderMode::Fresh));
}

TEST(RunFolder, RefusesNonEmptyFolderWithoutForce) {
  const fs::path d = fresh("occupied");
  fs::create_directories(d / "frames");
  touch(d / "stats.csv");
  touch(d / "frames" / "000001.png");
  touch(d / "notes.txt", "keep me");
  const std::string msg = error_of(d, RunFolderMode::Fresh);
  EXPECT_NE(msg.find("run folder '" + d.string() + "' is not empty"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--force"), std::string::npos) << msg;
  EXPECT_TRUE(fs::exists(d / "stats.csv"));  // nothing touched
}

// --force into a folder that no grainflow run wrote removes nothing and says why.
TEST(RunFolder, ForceRefusesAFolderHoldingNoGrainflowRun) {
  const fs::path d = fresh("users_own");
  fs::create_directories(d / "frames");
  touch(d / "holiday.mp4", "mine");
  touch(d / "frames" / "notes.txt", "mine");
  touch(d / "scene.toml", "mine");
  const std::string msg = error_of(d, RunFolderMode::Force);
  EXPECT_NE(msg.find("holds no grainflow run"), std::string::npos) << msg;
  EXPECT_EQ(msg.find(".grainflow-lock"), std::string::npos) << msg;  // the user's files only
  for (const char* f : {"holiday.mp4", "frames/notes.txt", "scene.toml"}) EXPECT_EQ(slurp(d / f), "mine") << f;
  EXPECT_FALSE(fs::exists(d / ".grainflow-lock"));
}

// --force removes exactly what the previous run claimed (with its temporaries), and
// every file a user put beside it survives.
TEST(RunFolder, ForceRemovesExactlyWhatThePreviousRunClaimed) {
  const fs::path d = fresh("previous");
  {
    RunFolder f = RunFolder::open(d, RunFolderMode::Fresh);
    for (const char* c : {"scene.toml", "run.json", "stats.csv", "run.mp4"}) f.claim(c);
    f.claim(kFrameFiles);
  }
  for (const char* mine : {"run.json", "scene.toml", "stats.csv.partial", "run.mp4.tmp-123-4", "frames/frame_000000.png",
                           "frames/frame_000001.png", "frames/frame_1000000.png"})
    touch(d / mine);
  for (const char* user : {"holiday.mp4", "frames/notes.txt", "frames/000001.png", "frames/frame_12.png", "run.mp4.bak"})
    touch(d / user, "mine");
  RunFolder::open(d, RunFolderMode::Force);
  for (const char* mine : {"run.json", "scene.toml", "stats.csv.partial", "run.mp4.tmp-123-4", "frames/frame_000000.png",
                           "frames/frame_000001.png", "frames/frame_1000000.png"})
    EXPECT_FALSE(fs::exists(d / mine)) << mine;
  for (const char* user : {"holiday.mp4", "frames/notes.txt", "frames/000001.png", "frames/frame_12.png", "run.mp4.bak"})
    EXPECT_EQ(slurp(d / user), "mine") << user;
}

// The file list is read back from disk: a name outside the folder is refused, nothing removed.
TEST(RunFolder, ForceDistrustsTheFileList) {
  const fs::path d = fresh("forged");
  fs::create_directories(d);
  touch(d / "keep.txt", "mine");
  touch(d / std::string(RunFolder::kManifest), "# forged\n../keep_outside.txt\nkeep.txt\n");
  const std::string msg = error_of(d, RunFolderMode::Force);
  EXPECT_NE(msg.find("not a grainflow file list"), std::string::npos) << msg;
  EXPECT_EQ(slurp(d / "keep.txt"), "mine");
}

// Any file name a scene may have is claimed (spaces, UTF-8); names with line breaks or
// outside the folder are refused with a message, not a crash.
TEST(RunFolder, ClaimsAnyPlainFileName) {
  const fs::path d = fresh("names");
  {
    RunFolder f = RunFolder::open(d, RunFolderMode::Fresh);
    f.claim("Düne 2.mp4");
    EXPECT_THROW(f.claim("a\nb.mp4"), grainflow::Error);
    EXPECT_THROW(f.claim("../x.mp4"), grainflow::Error);
    EXPECT_THROW(f.claim("/tmp/x.mp4"), grainflow::Error);
  }
  touch(d / "Düne 2.mp4");
  RunFolder::open(d, RunFolderMode::Force);
  EXPECT_FALSE(fs::exists(d / "Düne 2.mp4"));
}

// A start that fails leaves no trace: a folder it created is gone again.
TEST(RunFolder, AbandonRemovesWhatTheFailedStartMade) {
  const fs::path d = fresh("abandoned") / "run";
  RunFolder f = RunFolder::open(d, RunFolderMode::Fresh);
  f.claim("stats.csv");
  touch(d / "stats.csv.partial");
  f.abandon();
  EXPECT_FALSE(fs::exists(d));
  EXPECT_TRUE(fs::exists(d.parent_path()));  // not created by this open: kept
}

TEST(RunFolder, UnwritableOrInvalidPath) {
  // Tests run as root, for whom chmod does not make a folder unwritable: use a path under
  // a regular file instead.
  std::string msg = error_of("/etc/passwd/run", RunFolderMode::Fresh);
  EXPECT_NE(msg.find("cannot create run folder '/etc/passwd/run': Not a directory"), std::string::npos) << msg;
  msg = error_of("/etc/passwd", RunFolderMode::Fresh);
  EXPECT_NE(msg.find("exists and is not a directory"), std::string::npos) << msg;
  msg = error_of("/proc/grainflow-run", RunFolderMode::Fresh);
  EXPECT_NE(msg.find("cannot create run folder '/proc/grainflow-run'"), std::string::npos) << msg;
  msg = error_of("", RunFolderMode::Fresh);
  EXPECT_NE(msg.find("empty path"), std::string::npos) << msg;
}

TEST(RunFolder, AFolderInUseIsRefusedUntilItsProcessLetsGo) {
  const fs::path d = fresh("locked");
  {
    const RunFolder live = RunFolder::open(d, RunFolderMode::Fresh);
    touch(d / "run.json", "{}");
    for (RunFolderMode m : {RunFolderMode::Force, RunFolderMode::Resume})
      EXPECT_NE(error_of(d, m).find("in use by another grainflow process"), std::string::npos);
    EXPECT_TRUE(fs::exists(d / "run.json"));  // --force removed nothing
  }
  // Released (as when the process ends, however it ends): --force goes ahead.
  RunFolder::open(d, RunFolderMode::Force);
  // A refused folder keeps no lock file of ours.
  const fs::path mine = fresh("users_own");
  fs::create_directories(mine);
  touch(mine / "holiday.mp4");
  EXPECT_NE(error_of(mine, RunFolderMode::Force).find("holds no grainflow run"), std::string::npos);
  EXPECT_FALSE(fs::exists(mine / RunFolder::kLock));
}

TEST(RunFolder, ResumeNeedsAPreviousRun) {
  const fs::path d = fresh("resume");
  EXPECT_NE(error_of(d, RunFolderMode::Resume).find("no such folder"), std::string::npos);
  fs::create_directories(d);
  touch(d / "stats.csv.partial");
  EXPECT_NE(error_of(d, RunFolderMode::Resume).find("holds no run of grainflow"), std::string::npos);
  touch(d / "run.json", "{}");
  EXPECT_NE(error_of(d, RunFolderMode::Resume).find(".grainflow-files"), std::string::npos);
  touch(d / ".grainflow-files", "stats.csv\n");
  {
    RunFolder f = RunFolder::open(d, RunFolderMode::Resume);
    // The previous run's claims carry over, and a failed resume removes none of its files.
    EXPECT_EQ(f.claimed(), std::vector<std::string>{"stats.csv"});
    f.claim("checkpoints/checkpoint_1.gfck");
    f.abandon();
  }
  EXPECT_TRUE(fs::exists(d / "stats.csv.partial"));  // resume keeps everything
  EXPECT_TRUE(fs::exists(d / "run.json"));
}

TEST(JsonWriter, StringEscaping) {
  EXPECT_EQ(json_string("plain"), "\"plain\"");
  EXPECT_EQ(json_string("a\"b\\c/d"), R"("a\"b\\c/d")");
  EXPECT_EQ(json_string("\n\r\t\b\f"), R"("\n\r\t\b\f")");
  EXPECT_EQ(json_string(std::string("\x01\x1f", 2)), R"("\u0001\u001f")");
  EXPECT_EQ(json_string(std::string("nul\0x", 5)), R"("nul\u0000x")");
  EXPECT_EQ(json_string("σ = 1 é"), "\"σ = 1 é\"");  // UTF-8 passes through
}

TEST(JsonWriter, NumbersAndStructure) {
  EXPECT_EQ(json_number(0.1), "0.1");
  EXPECT_EQ(json_number(1e300), "1e+300");
  EXPECT_EQ(json_number(3.0), "3");
  EXPECT_EQ(json_number(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(json_number(-std::numeric_limits<double>::infinity()), "null");
  JsonWriter w;
  w.begin_object();
  w.key("a").value(1);
  w.key("b").begin_array().value("x").value(true).null().end_array();
  w.key("c").begin_object().end_object();
  w.key("d").begin_array().end_array();
  w.end_object();
  EXPECT_TRUE(w.complete());
  EXPECT_EQ(w.str(), "{\n  \"a\": 1,\n  \"b\": [\n    \"x\",\n    true,\n    null\n  ],\n  \"c\": {},\n  \"d\": []\n}");
  JsonWriter bad;
  bad.begin_object();
  EXPECT_THROW(bad.value(1), std::logic_error);  // value without key
  EXPECT_THROW(bad.end_array(), std::logic_error);
}

TEST(RunRecord, JsonHoldsRunFacts) {
  const Scene s = parse_scene("[run]\nengine = \"ed\"\nuntil = 100.0\nseed = 9\ntitle = \"a \\\"q\\\"\"\n[system]\nN = 5\n",
                              "t.toml", {"render.backend=egl"});
  RunRecord r = make_run_record(s);
  EXPECT_EQ(r.seed, 9);
  EXPECT_EQ(r.engine, "ed");
  EXPECT_EQ(r.backend, "");  // the run loop records the GL backend it got, not the one asked for
  EXPECT_EQ(r.target_kind, "until");
  EXPECT_EQ(r.target, 100.0);
  EXPECT_EQ(r.started_utc.size(), 20u);  // 2024-05-01T12:34:56Z
  r.status = RunStatus::Interrupted;
  r.wall_time_s = 12.5;
  r.sim_time = 40.0;
  r.throughput.push_back({"collisions", 2.5e6, "collisions/s"});
  r.figures.emplace_back("events", 3.0e7);
  const fs::path d = fresh("record");
  fs::create_directories(d);
  write_run_record(r, d / "run.json");
  const std::string j = slurp(d / "run.json");
  EXPECT_NE(j.find("\"status\": \"interrupted\""), std::string::npos) << j;
  EXPECT_NE(j.find("\"seed\": 9,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"title\": \"a \\\"q\\\"\""), std::string::npos) << j;
  EXPECT_NE(j.find("\"wall_time_s\": 12.5,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"until\": 100,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"collisions\": {\n      \"per_second\": 2500000,\n      \"unit\": \"collisions/s\"\n    }"),
            std::string::npos)
      << j;
  EXPECT_NE(j.find("\"overrides\": [\n    \"render.backend=egl\"\n  ]"), std::string::npos) << j;
  EXPECT_NE(j.find("\"grainflow_version\": \""), std::string::npos) << j;
  EXPECT_EQ(run_status_name(RunStatus::Complete), "complete");
  EXPECT_EQ(run_status_name(RunStatus::Running), "running");
}
