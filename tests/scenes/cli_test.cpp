// End-to-end tests of the `grainflow` executable: `render` and `run` produce their
// outputs, and bad input gives a clear message and exit status 2 without leaving a
// finished-looking file behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <chrono>
#include <csignal>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include "render/image/image.hpp"
#include "render/output/png_io.hpp"
#include "tests/render/mp4_test_support.hpp"
#include "tests/scenes/cli_support.hpp"

namespace fs = std::filesystem;

namespace {

const std::string data = GRAINFLOW_TEST_DATA;
const std::string scenes = GRAINFLOW_SCENES_DIR;

void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The "state_digest" in the text of a run.json: hex fingerprint of the final state.
std::string digest_in(const std::string& run_json) {
  const auto k = run_json.find("\"state_digest\": \"");
  if (k == std::string::npos) return {};
  return run_json.substr(k + 17, 16);
}
std::string state_digest(const fs::path& run_dir) { return digest_in(read_file(run_dir / "run.json")); }

TEST(CliRender, LammpsDumpToPngAndMp4) {
  const fs::path out = fresh_dir("render_lammps");
  const Result r = run("render " + data + "/particles/lammps_two_frames.lammpstrj -o " + out.string() +
                       " --size 160 120");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "frames/frame_000000.png"));
  EXPECT_TRUE(fs::exists(out / "frames/frame_000001.png"));
  EXPECT_FALSE(fs::exists(out / "frames/frame_000002.png"));
  EXPECT_GT(fs::file_size(out / "lammps_two_frames.mp4"), 0u);
  const auto img = grainflow::render::read_png(out / "frames/frame_000000.png");
  EXPECT_EQ(img.width, 160);
  EXPECT_EQ(img.height, 120);
}

TEST(CliRender, XyzWithOddSizeAndColourColumn) {
  const fs::path out = fresh_dir("render_xyz");
  const Result r = run("render " + data + "/particles/extended_two_frames.xyz -o " + out.string() +
                       " --size 161 97 --color-by radius --colormap magma --no-mp4");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "frames/frame_000001.png"));
  EXPECT_FALSE(fs::exists(out / "extended_two_frames.mp4"));
}

TEST(CliRender, MissingFileIsAnError) {
  const fs::path out = fresh_dir("render_missing");
  const Result r = run("render " + data + "/particles/no_such_file.xyz -o " + out.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "no_such_file.xyz")) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliRender, MalformedFileNamesTheLineAndLeavesNoVideo) {
  // A short line followed by its '\n' is a malformed file, not one still being written
  // (that case: CliRender.PourStillBeingWrittenRendersItsCompleteFrames).
  const fs::path out = fresh_dir("render_malformed");
  const Result r = run("render " + data + "/particles/malformed/short_line.lammpstrj -o " + out.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "short_line.lammpstrj:11:")) << r.output;
  EXPECT_FALSE(fs::exists(out / "short_line.mp4"));
  if (fs::exists(out)) {
    for (const auto& f : fs::recursive_directory_iterator(out)) EXPECT_NE(f.path().extension(), ".mp4") << f.path();
  }
}

TEST(CliRender, UnknownBackendIsAnError) {
  const fs::path out = fresh_dir("render_backend");
  const Result r = run("render " + data + "/particles/plain_two_frames.xyz -o " + out.string() + " --backend vulkan");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "vulkan")) << r.output;
  EXPECT_TRUE(contains(r.output, "auto, egl, osmesa")) << r.output;
  EXPECT_FALSE(fs::exists(out));  // nothing is created for a command that cannot run
}

TEST(CliRender, RefusesToOverwriteEarlierFramesWithoutForce) {
  const fs::path out = fresh_dir("render_twice");
  const std::string args = "render " + data + "/particles/plain_two_frames.xyz -o " + out.string() + " --size 64 48";
  ASSERT_EQ(run(args).status, 0);
  const Result r = run(args);
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "--force")) << r.output;
  EXPECT_EQ(run(args + " --force").status, 0);
}

TEST(CliRender, NonFiniteOptionsAreRefusedBeforeTheFolderExists) {
  for (const char* opt : {"--azimuth nan", "--elevation inf", "--range 0 inf"}) {
    const fs::path out = fresh_dir("render_nonfinite");
    const Result r = run("render " + data + "/particles/plain_two_frames.xyz -o " + out.string() + " " + opt);
    EXPECT_EQ(r.status, 2) << opt << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, "finite")) << r.output;
    EXPECT_FALSE(fs::exists(out)) << opt;
  }
}

TEST(CliRender, ZeroOrAbsurdSizeIsAnError) {
  for (const char* size : {"0 100", "100000 100", "-5 10"}) {
    const fs::path out = fresh_dir("render_size");
    const Result r = run("render " + data + "/particles/plain_two_frames.xyz -o " + out.string() + " --size " + size);
    EXPECT_EQ(r.status, 2) << size;
    EXPECT_TRUE(contains(r.output, "--size")) << r.output;
    EXPECT_FALSE(fs::exists(out / "frames/frame_000000.png"));
  }
}

TEST(CliRender, UnwritableOutputIsAnError) {
  // Root may write anywhere, so use a path below a regular file.
  const Result r = run("render " + data + "/particles/plain_two_frames.xyz -o /etc/hostname/out");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "/etc/hostname/out")) << r.output;
}

TEST(CliRender, UnknownColourColumnListsTheColumns) {
  const fs::path out = fresh_dir("render_column");
  const Result r = run("render " + data + "/particles/lammps_two_frames.lammpstrj -o " + out.string() +
                       " --color-by temperature");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "temperature")) << r.output;
  EXPECT_TRUE(contains(r.output, "speed")) << r.output;
}

TEST(CliRun, DisksBoxWritesTheRunFolder) {
  const fs::path out = fresh_dir("run_box");
  const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() +
                       " --set system.box=[20.0,20.0] --set run.until=4.0 --set render.size=[128,128]");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"scene.toml", "stats.csv", "run.json", "disks_box.mp4", "frames/frame_000002.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_FALSE(fs::exists(out / "stats.csv.partial"));
  std::ifstream csv(out / "stats.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("time,collisions,", 0), 0u) << header;
  std::ifstream json(out / "run.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(text, "\"status\": \"complete\"")) << text;
  // The effective scene records the overrides and runs again as it is.
  const fs::path again = fresh_dir("run_box_again");
  const Result r2 = run("run " + (out / "scene.toml").string() + " -o " + again.string());
  EXPECT_EQ(r2.status, 0) << r2.output;
  // Same scene + seed ⇒ same numbers.
  std::ifstream a(out / "stats.csv"), b(again / "stats.csv");
  const std::string sa((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
  const std::string sb((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
  EXPECT_EQ(sa, sb);
}

// Runs `scene` with `settings` and system.lanes = 2 on one thread and on two; expects the
// same stats.csv and state digest (run.json), and returns run.json of the two-thread run.
std::string expect_lanes_same_on_one_thread_and_two(const std::string& scene, const std::string& settings,
                                                    const std::string& name) {
  std::string stats[2], digest[2], text;
  for (int k = 0; k < 2; ++k) {
    const fs::path out = fresh_dir(name + "_" + std::to_string(k + 1));
    const Result r = run("run " + scenes + "/" + scene + " -o " + out.string() + " " + settings +
                         " --set system.lanes=2 --set output.png=false --set output.mp4=false --threads " +
                         std::to_string(k + 1));
    EXPECT_EQ(r.status, 0) << r.output;
    stats[k] = read_file(out / "stats.csv");
    text = read_file(out / "run.json");
    digest[k] = digest_in(text);
    EXPECT_FALSE(digest[k].empty()) << text;
  }
  EXPECT_GT(stats[0].size(), 100u);
  EXPECT_EQ(stats[0], stats[1]);
  EXPECT_FALSE(digest[0].empty());
  EXPECT_EQ(digest[0], digest[1]);
  return text;
}

TEST(CliRun, EdLanesGiveTheSameRunOnOneThreadAndTwo) {
  // system.lanes = 2 (the two-lane loop, its sampler acting at stops): --threads decides
  // only how it runs.
  expect_lanes_same_on_one_thread_and_two("disks_box.toml", "--set system.box=[40.0,40.0] --set run.until=12.0",
                                          "run_lanes");
  // A box too small to cut is refused, saying why.
  const Result bad = run("run " + scenes + "/disks_box.toml -o " + fresh_dir("run_lanes_bad").string() +
                         " --set system.box=[12.0,12.0] --set system.lanes=2");
  EXPECT_NE(bad.status, 0) << bad.output;
  EXPECT_TRUE(contains(bad.output, "rows of cells")) << bad.output;
}

TEST(CliRun, EdLanesRunTheDuneWithTheSameRunOnOneThreadAndTwo) {
  // The quick dune (dispenser and filter, a no-slip obstacle on the cut, the TC model from
  // the inelastic phase on) in two lanes: the same stats and digest on one thread and two.
  const std::string json = expect_lanes_same_on_one_thread_and_two(
      "dune_quick.toml",
      "--set system.box=[80.0,40.0] --set boundary.obstacle.x=24.0 --set boundary.obstacle.y=20.0"
      " --set boundary.obstacle.D=8.0 --set 'phase[1].at=40.0' --set run.until=80.0 --set sample.exposure=20.0"
      " --set 'sample.bins=[40,20]'",
      "run_lanes_dune");
  EXPECT_TRUE(contains(json, "\"lanes\": 2")) << json;
  EXPECT_TRUE(contains(json, "\"lane_runs_redone\"")) << json;
}

TEST(CliRun, EdLanesSayWhenTheyRedidManyRuns) {
  // A strongly inelastic stream (e = 0.3) clusters on the cut: the lanes do many runs
  // again in the one-thread order, and the run says so after its closing line.
  const fs::path out = fresh_dir("run_lanes_advice");
  const Result r = run("run " + scenes + "/dune_quick.toml -o " + out.string() +
                       " --set system.box=[90.0,48.0] --set boundary.obstacle.x=30.0 --set boundary.obstacle.y=24.0"
                       " --set boundary.obstacle.D=12.0 --set 'phase[1].at=30.0' --set 'phase[1].e=0.3'"
                       " --set 'phase[1].obstacle_r=0.3' --set run.until=250.0 --set sample.exposure=50.0"
                       " --set 'sample.bins=[45,24]' --set system.lanes=2 --set output.png=false"
                       " --set output.mp4=false --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string text = read_file(out / "run.json");
  auto figure = [&text](const std::string& name) {
    const auto at = text.find("\"" + name + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + name.size() + 4));
  };
  const double runs = figure("lane_runs"), redone = figure("lane_runs_redone");
  ASSERT_GE(runs, 8.0) << text;
  ASSERT_GE(redone, 0.0) << text;
  // The advice follows the counts (a quarter done again); here it is nearly always given.
  EXPECT_EQ(contains(r.output, "were done again in the one-thread order"), 4.0 * redone > runs) << r.output;
  std::printf("  %g of %g runs done again\n", redone, runs);
}

TEST(CliRun, DemFreeFallFollowsGravityAndDrawsPanels) {
  const fs::path out = fresh_dir("run_dem");
  const Result r = run("run " + scenes + "/dem_freefall_box.toml -o " + out.string() +
                       " --set 'system.group[0].N=300' --set run.until=0.01 --set sample.exposure=0.005"
                       " --set 'system.initial.kind=\"lattice\"'"
                       " --set 'render.size=[240,160]' --set 'render.layout=[2,1]'"
                       " --set 'render.panels=[\"particles\",\"fraction\"]'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "frames/frame_000002.png"));
  // Free fall from rest: kinetic energy N·m·(g t)²/2 (no contacts yet in the dilute lattice).
  std::ifstream csv(out / "stats.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  double t = 0, step = 0, n = 0, ke = 0;
  ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf", &t, &step, &n, &ke), 4) << row;
  const double m = 2500.0 * 4.0 / 3.0 * M_PI * std::pow(0.5e-3, 3);
  EXPECT_NEAR(ke, n * 0.5 * m * std::pow(9.81 * t, 2), 1e-3 * ke);
}

TEST(CliRun, RefusesToOverwriteAPreviousRun) {
  const fs::path out = fresh_dir("run_twice");
  const std::string args = "run " + scenes + "/disks_box.toml -o " + out.string() +
                           " --set system.box=[20.0,20.0] --set run.until=2.0 --set render.size=[64,64]";
  ASSERT_EQ(run(args).status, 0);
  const Result r = run(args);
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "--force")) << r.output;
  EXPECT_EQ(run(args + " --force").status, 0);
}

// DEM fields: bins two diameters wide unless sample.bins is given; a slab or fill height
// the box cannot hold is refused, naming the key.
TEST(CliRun, DemFieldBinsFollowTheDiameterAndSlabIsChecked) {
  const std::string base = "run " + scenes + "/dem_freefall_box.toml --set 'system.group[0].N=300'"
                           " --set run.until=0.004 --set sample.exposure=0.002 --set system.initial.grow_steps=100"
                           " --set output.png=false --set output.mp4=false --set output.fields=true";
  const fs::path out = fresh_dir("run_dem_bins");
  Result r = run(base + " -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  // 0.04 m box, radius 0.5 mm: 20 × 20 bins of 2 mm on x–z; one cell across the slab
  // y = 0.01 … 0.03 m of the scene.
  std::string vti = read_file(out / "fields" / "frame_000002.vti");
  EXPECT_TRUE(contains(vti, "WholeExtent=\"0 20 0 1 0 20\" Origin=\"0 0.01 0\" Spacing=\"0.002 0.0199999"))
      << vti.substr(0, 400);
  const fs::path given = fresh_dir("run_dem_bins_given");
  r = run(base + " -o " + given.string() + " --set 'sample.bins=[8,4]'");
  ASSERT_EQ(r.status, 0) << r.output;
  vti = read_file(given / "fields" / "frame_000002.vti");
  EXPECT_TRUE(contains(vti, "WholeExtent=\"0 8 0 1 0 4\"")) << vti.substr(0, 400);
  r = run(base + " -o " + fresh_dir("run_dem_slab").string() + " --set 'sample.slab=[0.05,0.06]'");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "sample.slab = [0.05, 0.06] must have lo < hi and overlap the box")) << r.output;
  r = run(base + " -o " + fresh_dir("run_dem_fill").string() + " --set system.initial.fill_height=0.05");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "system.initial.fill_height = 0.05 m is taller than the box")) << r.output;
}

// --force touches only what grainflow wrote: a folder of the user's own is refused as a
// whole, and beside a previous run the user's files survive its replacement.
TEST(CliRun, ForceKeepsTheUsersOwnFiles) {
  const fs::path out = fresh_dir("run_users_folder");
  for (const char* f : {"holiday.mp4", "frames/notes.txt", "scene.toml"}) write_file(out / f, "mine");
  const std::string args = "run " + scenes + "/disks_box.toml -o " + out.string() +
                           " --set system.box=[20.0,20.0] --set run.until=4.0 --set render.size=[64,64] --force";
  const Result r = run(args);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "holds no grainflow run")) << r.output;
  for (const char* f : {"holiday.mp4", "frames/notes.txt", "scene.toml"}) EXPECT_EQ(read_file(out / f), "mine") << f;

  // A previous run with the user's files put beside it.
  const fs::path run_dir = fresh_dir("run_beside_users");
  ASSERT_EQ(run("run " + scenes + "/disks_box.toml -o " + run_dir.string() +
                " --set system.box=[20.0,20.0] --set run.until=8.0 --set render.size=[64,64]")
                .status,
            0);
  EXPECT_TRUE(fs::exists(run_dir / "frames/frame_000004.png"));
  for (const char* f : {"holiday.mp4", "frames/notes.txt"}) write_file(run_dir / f, "mine");
  const Result again = run("run " + scenes + "/disks_box.toml -o " + run_dir.string() +
                           " --set system.box=[20.0,20.0] --set run.until=2.0 --set render.size=[64,64] --force");
  ASSERT_EQ(again.status, 0) << again.output;
  for (const char* f : {"holiday.mp4", "frames/notes.txt"}) EXPECT_EQ(read_file(run_dir / f), "mine") << f;
  EXPECT_TRUE(fs::exists(run_dir / "frames/frame_000001.png"));  // τ_E = 2: frames 0, 1
  EXPECT_FALSE(fs::exists(run_dir / "frames/frame_000004.png"));  // the previous run's, removed
  EXPECT_TRUE(fs::exists(run_dir / "disks_box.mp4"));
}

// The manifest names frames/frame_*.png; were frames/ replaced by a link to a folder of the
// user's, --force must neither delete the user's numbered files there nor write over them.
TEST(CliRun, ForceDoesNotRemoveThroughALinkedFolder) {
  const fs::path run_dir = fresh_dir("run_linked_frames");
  const std::string args = "run " + scenes + "/disks_box.toml -o " + run_dir.string() +
                           " --set system.box=[20.0,20.0] --set run.until=4.0 --set render.size=[64,64]";
  ASSERT_EQ(run(args).status, 0);
  const fs::path users = fresh_dir("users_numbered_pictures");
  write_file(users / "frame_000001.png", "mine");
  fs::remove_all(run_dir / "frames");
  fs::create_directory_symlink(users, run_dir / "frames");
  const Result r = run(args + " --force");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "is a link")) << r.output;
  EXPECT_EQ(read_file(users / "frame_000001.png"), "mine");
  EXPECT_TRUE(fs::is_symlink(run_dir / "frames"));
}

// A start that fails (the engine's set-up, an output option) leaves no folder behind, so
// the corrected command is not refused.
TEST(CliRun, FailedStartLeavesNoFolder) {
  const fs::path out = fresh_dir("run_failed_start");
  const Result r = run("run " + scenes + "/dem_freefall_box.toml -o " + out.string() +
                       " --set system.box=[0.004,0.004,0.004] --set system.initial.kind=lattice"
                       " --set sample.slab=[0.0,0.004]");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "lattice")) << r.output;
  EXPECT_FALSE(fs::exists(out));
  const fs::path render_out = fresh_dir("render_failed_start");
  const Result rr = run("render " + data + "/particles/plain_two_frames.xyz -o " + render_out.string() +
                        " --size 64 48 --preset sloth");
  EXPECT_EQ(rr.status, 2) << rr.output;
  EXPECT_TRUE(contains(rr.output, "preset")) << rr.output;
  EXPECT_FALSE(fs::exists(render_out));
  EXPECT_EQ(run("render " + data + "/particles/plain_two_frames.xyz -o " + render_out.string() + " --size 64 48").status,
            0);
}

// SIGTERM is honoured within a second even inside an engine slice: an inelastic box
// (e = 0.5) collapses after t ≈ 52 — its clock stops while collisions go on — and used to
// ignore the signal for minutes. It stops as "interrupted" with its outputs in place.
// A collapsing inelastic box (e = 0.5 without the TC model) keeps the engine busy while
// the clock stands still; the collapse guard is switched off here, so only the signal ends it.
TEST(CliRun, SigtermStopsACollapsingRunWithinASecond) {
  const fs::path out = fresh_dir("run_collapse");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string dir = out.string();
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    execl(GRAINFLOW_EXE, GRAINFLOW_EXE, "run", (scenes + "/disks_box.toml").c_str(), "-o", dir.c_str(), "--set",
          "system.e=0.5", "--set", "system.collapse_events=0", "--set", "run.until=1e6", "--set", "render.size=[64,64]",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::seconds(4));  // collapsed by then (t stalls near 52)
  const auto t0 = std::chrono::steady_clock::now();
  kill(pid, SIGTERM);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(10)) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      FAIL() << "no exit within 10 s of SIGTERM";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 1.5);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(contains(read_file(out / "run.json"), "\"status\": \"interrupted\""));
  EXPECT_TRUE(fs::exists(out / "stats.csv"));
  EXPECT_TRUE(fs::exists(out / "disks_box.mp4"));
}

// What a scene may ask of the machine is bounded at validation, with the estimate.
TEST(CliRun, ScenesBeyondTheMachineAreRefusedWithTheEstimate) {
  const fs::path out = fresh_dir("run_too_big");
  for (const auto& [args, needle] : std::vector<std::pair<std::string, std::string>>{
           {"/disks_box.toml --set system.box=[2e4,2e4]", "GB for 3.31e+08 disks; this machine has"},
           {"/disks_box.toml --set system.box=[1e5,1e5]", "at most 2147483647"},
           {"/dem_freefall_box.toml --set system.group[0].N=1000000000", "GB for 1e+09 spheres"},
           {"/disks_box.toml --set sample.exposure=1e-300", "at most 1e7 frames"}}) {
    // The first case needs ≈ 85 GB: on a machine that large it is a legal (long) run.
    if (contains(needle, "3.31e+08") && double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) > 80e9)
      continue;
    const Result r = run("run " + scenes + args + " -o " + out.string());
    EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, needle)) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

// The cell grid costs memory whatever the density: a sparse box of 10 disks in 10^5 × 10^5
// asks for 6.9e9 cells.
TEST(CliRun, ACellGridBeyondTheEngineIsRefused) {
  const fs::path dir = fresh_dir("run_sparse");
  write_file(dir.parent_path() / "sparse.toml", "[run]\nengine = \"ed\"\nuntil = 1.0\n[system]\nbox = [1.0e5, 1.0e5]\nN = 10\n");
  const Result r = run("run " + (dir.parent_path() / "sparse.toml").string() + " -o " + dir.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "6.94e+09 cells")) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}

// A state that turns non-finite ends "failed" naming the quantity, not "complete" with NaN.
TEST(CliRun, NonFiniteStateFailsTheRun) {
  const fs::path out = fresh_dir("run_nonfinite");
  const Result r = run("run " + scenes + "/dem_vdw_pair.toml -o " + out.string() +
                       " --set system.gravity=[0.0,0.0,-1e300] --set run.until=1e-7 --set output.mp4=false");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "no longer finite")) << r.output;
  const std::string json = read_file(out / "run.json");
  EXPECT_TRUE(contains(json, "\"status\": \"failed\"")) << json;
  EXPECT_TRUE(contains(json, "kinetic energy")) << json;
}

// run.max_wall stops a run cleanly as interrupted.
TEST(CliRun, MaxWallStopsTheRunAsInterrupted) {
  const fs::path out = fresh_dir("run_max_wall");
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() +
                       " --set run.until=1e6 --set run.max_wall=1.0 --set render.size=[64,64]");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, 130) << r.output;
  EXPECT_TRUE(contains(r.output, "run.max_wall")) << r.output;
  EXPECT_LT(seconds, 6.0);
  EXPECT_TRUE(contains(read_file(out / "run.json"), "\"status\": \"interrupted\""));
}

TEST(CliRun, BadSceneStopsBeforeTheRunWithKeyAndValue) {
  const fs::path out = fresh_dir("run_bad");
  const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() +
                       " --set system.area_fraction=0.95 --set render.colour=1");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "system.area_fraction")) << r.output;
  EXPECT_TRUE(contains(r.output, "0.95")) << r.output;
  EXPECT_TRUE(contains(r.output, "render.colour")) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// Choices a run cannot honour are refused by validation, with the names its tables allow,
// before any folder exists (the colour attribute comes from the engine's table: a 2D
// engine has no vz; panels and colour maps from the renderer's tables).
TEST(CliRun, ChoicesTheRunCannotHonourAreRefusedBeforeTheFolderExists) {
  struct Bad {
    std::string set, needle;
  };
  for (const Bad& b : {Bad{"render.color_by=vz", "\"uniform\" | \"speed\" | \"vx\" | \"vy\" | \"spin\" | \"height\""},
                       Bad{"render.panels=[\\\"nonsense\\\"]", "\"particles\" | \"density\""},
                       Bad{"render.colormap=jet", "\"viridis\" | \"inferno\""}}) {
    const fs::path out = fresh_dir("run_refused");
    const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() + " --set \"" + b.set + "\"");
    EXPECT_EQ(r.status, 2) << b.set << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, "allowed: ")) << r.output;
    EXPECT_TRUE(contains(r.output, b.needle)) << r.output;
    EXPECT_FALSE(fs::exists(out)) << b.set;
  }
  // The 3D engine offers vz.
  const fs::path out = fresh_dir("run_vz");
  const Result r = run("run " + scenes + "/dem_vdw_pair.toml -o " + out.string() +
                       " --set render.color_by=vz --set run.until=1e-8 --set render.size=[64,64] --set output.mp4=false");
  EXPECT_EQ(r.status, 0) << r.output;
}

// Frames are taken at exactly t0 + k·τ_E, after every event due then: a frame taken a
// round-off before its time (slices of τ_E/20 summed) would miss the sampler's end of
// exposure and show the previous exposure's fields again.
TEST(CliRun, FramesAreTakenAtTheirExactTimes) {
  const fs::path out = fresh_dir("run_frame_times");
  const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() +
                       " --set sample.exposure=8.0 --set run.until=80.0 --set output.particles=true"
                       " --set output.mp4=false --set output.png=false --set render.size=[64,64]");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(out / "particles.xyz");
  std::string line;
  std::vector<std::string> times;
  while (std::getline(in, line))
    if (auto p = line.find(" Time="); p != std::string::npos)
      times.push_back(line.substr(p + 6, line.find(' ', p + 6) - p - 6));
  ASSERT_EQ(times.size(), 11u);
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_EQ(times[k], std::to_string(8 * k)) << "frame " << k;
}

// Rows of a CSV file with a header: column name → values.
std::map<std::string, std::vector<double>> read_csv(const fs::path& file) {
  std::map<std::string, std::vector<double>> cols;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::size_t a = 0, b; a <= line.size(); a = b + 1) {
    b = std::min(line.find(',', a), line.size());
    names.push_back(line.substr(a, b - a));
  }
  while (std::getline(in, line)) {
    std::size_t a = 0;
    for (const auto& n : names) {
      std::size_t b = std::min(line.find(',', a), line.size());
      cols[n].push_back(std::stod(line.substr(a, b - a)));
      a = b + 1;
    }
  }
  return cols;
}

// The TC model through the scene (seed 003 ch. 5): the e = 0.5 box with a cutoff cools
// to its end; stats.csv carries the cutoff and the removals. Started without a cutoff but
// with a step, the first collision below the clock's precision removes its disk (a line
// on stderr with time and position), and the cutoff becomes the step.
TEST(CliRun, InelasticBoxWithTheTimeCutoffCompletesAndCools) {
  for (const std::string tc : {"--set system.tau_tc=1e-4", "--set system.tau_tc_step=1e-4"}) {
    SCOPED_TRACE(tc);
    const fs::path out = fresh_dir("run_tc");
    const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() +
                         " --set system.e=0.5 " + tc + " --set run.until=100 --set output.mp4=false --set output.png=false");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(contains(r.output, "without the TC model")) << r.output;
    EXPECT_TRUE(contains(read_file(out / "run.json"), "\"status\": \"complete\""));
    auto cols = read_csv(out / "stats.csv");
    ASSERT_EQ(cols.count("removed_overlap"), 1u);
    ASSERT_EQ(cols.count("tau_tc"), 1u);
    const auto& kT = cols["kT"];
    ASSERT_EQ(kT.size(), 50u);
    EXPECT_EQ(cols["time"].back(), 100.0);
    EXPECT_LT(kT.back(), 0.05 * kT.front());
    // Energy only leaves; a removal may lift the mean a hair (a slow disk gone).
    for (std::size_t k = 5; k < kT.size(); ++k) EXPECT_LT(kT[k], kT[k - 5]) << "row " << k;
    EXPECT_EQ(cols["tau_tc"].back(), 1e-4);
    const double removed = cols["removed_overlap"].back();
    EXPECT_EQ(cols["N"].back(), cols["N"].front() - (removed - cols["removed_overlap"].front()));
    if (contains(tc, "step")) {
      EXPECT_GE(removed, 1.0);
      EXPECT_EQ(cols["tau_tc"].front(), 0.0);  // the first row is before the removal (t ≈ 26)
      EXPECT_TRUE(contains(r.output, "overlapped and was removed; tau_tc → 0.0001")) << r.output;
      EXPECT_TRUE(contains(r.output, "grainflow: t = 26.")) << r.output;
    } else {
      EXPECT_EQ(removed, 0.0);
    }
  }
}

// Without the TC model the same box collapses (its clock stalls at t ≈ 52–54, the moment
// depending on the trajectory's last bits): the run is warned at the start, and fails,
// saying what happened and what to do, instead of spinning.
TEST(CliRun, ACollapsingInelasticRunFailsWithWhatToDo) {
  const fs::path out = fresh_dir("run_collapse_guard");
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() +
                       " --set system.e=0.5 --set run.until=1e6 --set system.collapse_events=2000000"
                       " --set output.mp4=false --set output.png=false");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "without the TC model")) << r.output;
  const std::string said = "ed: the system collapsed at t = ";
  const std::size_t at = r.output.find(said);
  ASSERT_NE(at, std::string::npos) << r.output;
  const double t_collapse = std::atof(r.output.c_str() + at + said.size());
  EXPECT_GT(t_collapse, 45.0) << r.output;
  EXPECT_LT(t_collapse, 60.0) << r.output;
  EXPECT_TRUE(contains(r.output, "system.tau_tc > 0")) << r.output;
  EXPECT_LT(seconds, 30.0);
  const std::string json = read_file(out / "run.json");
  EXPECT_TRUE(contains(json, "\"status\": \"failed\"")) << json;
  EXPECT_TRUE(contains(json, "collapsed")) << json;
  EXPECT_TRUE(fs::exists(out / "stats.csv.partial"));  // the rows up to the collapse, as any failed run
}

TEST(CliRun, DemVanDerWaalsPairOscillatesAndSettles) {
  // Seed 000 §5.4 through the scene: two spheres released 5 nm apart attract, collide and
  // stay bound, each rebound lower than the last (Fig. 5.14–5.16).
  const fs::path out = fresh_dir("run_vdw_pair");
  const Result r = run("run " + scenes + "/dem_vdw_pair.toml -o " + out.string() +
                       " --set run.until=2.5e-5 --set sample.exposure=1.25e-5 --set output.mp4=false"
                       " --set 'render.size=[64,64]' --set output.pair_every=5");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "pair.csv.partial"));
  auto csv = read_csv(out / "pair.csv");
  const auto& gap = csv["separation"];
  ASSERT_GT(gap.size(), 10000u);
  // Row 0: at rest, 5 nm apart, only the attraction of Eq. 5.28: A R/(12 α²).
  const double R = 3.175e-5, A = 1e-18, gap0 = 5e-9;
  EXPECT_NEAR(gap[0], gap0, 1e-15);
  EXPECT_NEAR(csv["vdw_force"][0], A * R / (12 * gap0 * gap0), 1e-6 * A * R / (12 * gap0 * gap0));
  EXPECT_NEAR(csv["normal_force"][0], -csv["vdw_force"][0], 1e-20);
  EXPECT_EQ(csv["contact_force"][0], 0.0);
  EXPECT_EQ(csv["step"][1], 5.0);
  // During overlap the spring pushes apart: contact force = K1·overlap while loading.
  double max_overlap = 0, max_spring = 0;
  for (std::size_t i = 0; i < gap.size(); ++i) {
    max_overlap = std::max(max_overlap, -gap[i]);
    max_spring = std::max(max_spring, csv["contact_force"][i]);
  }
  EXPECT_NEAR(max_spring, 1e7 * max_overlap, 0.02 * max_spring);
  // Largest separation of each excursion between contacts.
  std::vector<double> peaks;
  double cur = -1;
  bool touching = false, contacted = false;
  for (double g : gap) {
    EXPECT_LE(g, gap0 * (1 + 1e-9));  // never back to the release separation
    if (g < 0 && !touching) {
      touching = true;
      if (contacted && cur > 0) peaks.push_back(cur);
      contacted = true;
      cur = -1;
    } else if (g >= 0) {
      touching = false;
      if (contacted) cur = std::max(cur, g);
    }
  }
  ASSERT_GE(peaks.size(), 4u);
  EXPECT_LT(peaks[0], gap0);
  for (std::size_t k = 1; k < peaks.size(); ++k) EXPECT_LT(peaks[k], peaks[k - 1]) << k;
}

TEST(CliRun, DemInitialFileErrorsNameTheNumbers) {
  const fs::path out = fresh_dir("run_file_count");
  const Result r = run("run " + scenes + "/dem_vdw_pair.toml -o " + out.string() +
                       " --set 'system.group[0].N=3' --set output.mp4=false");
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(contains(r.output, "has 2 particles")) << r.output;
  EXPECT_TRUE(contains(r.output, "add up to 3")) << r.output;
  EXPECT_FALSE(fs::exists(out / "pair.csv"));
}

TEST(CliRun, DemCouetteTopLayerFollowsTheSlidingWall) {
  // Plane Couette: the top wall slides along +x at U, the bottom wall rests; after a short
  // run the spheres next to the top move along +x faster than those next to the bottom.
  const fs::path out = fresh_dir("run_couette");
  const double U = 0.2, Lz = 0.008, d = 1e-3;
  const Result r = run("run " + scenes + "/dem_couette.toml -o " + out.string() +
                       " --set 'system.group[0].N=300' --set 'system.box=[0.008,0.006,0.008]'"
                       " --set system.initial.grow_steps=500 --set run.until=0.03 --set sample.exposure=0.03"
                       " --set output.mp4=false --set output.particles=true --set render.color_by=vx"
                       " --set 'render.size=[64,32]'");
  ASSERT_EQ(r.status, 0) << r.output;
  // Last frame of particles.xyz: columns id type x y z radius vx vy vz ….
  std::ifstream in(out / "particles.xyz");
  std::string line, last_header;
  std::vector<std::array<double, 2>> zvx;  // (z, vx) of the last frame
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::size_t n = std::stoul(line);
    std::getline(in, last_header);
    zvx.clear();
    for (std::size_t i = 0; i < n && std::getline(in, line); ++i) {
      long long id;
      int type;
      double x, y, z, rad, vx;
      ASSERT_EQ(std::sscanf(line.c_str(), "%lld %d %lf %lf %lf %lf %lf", &id, &type, &x, &y, &z, &rad, &vx), 7) << line;
      zvx.push_back({z, vx});
    }
  }
  ASSERT_TRUE(contains(last_header, "radius:R:1:velo:R:3")) << last_header;
  EXPECT_TRUE(contains(last_header, "pbc=\"T T F\"")) << last_header;  // periodic along the wall
  ASSERT_EQ(zvx.size(), 300u);
  double top = 0, bottom = 0;
  int ntop = 0, nbottom = 0;
  for (const auto& [z, vx] : zvx) {
    EXPECT_LT(vx, 1.2 * U);  // nothing outruns the wall by much
    if (z > Lz - 2 * d) top += vx, ++ntop;
    if (z < 2 * d) bottom += vx, ++nbottom;
  }
  ASSERT_GT(ntop, 10);
  ASSERT_GT(nbottom, 10);
  top /= ntop;
  bottom /= nbottom;
  EXPECT_GT(top, 0.15 * U) << "top layer mean vx " << top;
  EXPECT_GT(top - bottom, 0.1 * U) << "top " << top << ", bottom " << bottom;
  EXPECT_LT(std::abs(bottom), 0.1 * U) << "bottom layer mean vx " << bottom;
}

TEST(CliRun, DemWallVelocityNeedsAWallAndInPlaneComponents) {
  const fs::path out = fresh_dir("run_couette_bad");
  Result r = run("run " + scenes + "/dem_couette.toml -o " + out.string() + " --set 'boundary.periodic=[true,true,true]'");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "boundary.top_velocity")) << r.output;
  EXPECT_TRUE(contains(r.output, "periodic")) << r.output;
  EXPECT_FALSE(fs::exists(out));
  r = run("run " + scenes + "/dem_couette.toml -o " + out.string() + " --set 'boundary.top_velocity=[0.2,0.0,0.1]'");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "boundary.top_velocity")) << r.output;
  EXPECT_FALSE(fs::exists(out));
  r = run("run " + scenes + "/dem_couette.toml -o " + out.string() + " --set boundary.top=\"open\"");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "boundary.top_velocity")) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace

TEST(CliRun, DemChainCellsAndAllPairsSearchGiveTheSameBits) {
  // Seed 000 §3: the chain-cell table and the N² reference hold the same pairs in the same
  // order, so the whole trajectory is bit-identical; the scene-level check of the 20,000
  // sphere run (README) uses the same digest. Contacts form within 0.03 s here.
  const std::string common = "run " + scenes + "/dem_freefall_box.toml --set 'system.group[0].N=800'"
                             " --set 'system.box=[0.012,0.012,0.03]' --set run.until=0.03 --set output.png=false"
                             " --set output.mp4=false --set 'render.size=[32,32]' -o ";
  const fs::path a = fresh_dir("search_cells"), b = fresh_dir("search_n2"), c = fresh_dir("search_cells_thick");
  ASSERT_EQ(run(common + a.string()).status, 0);
  ASSERT_EQ(run(common + b.string() + " --set system.neighbor_search=all_pairs").status, 0);
  // A different time step is a different trajectory: the digest must tell the runs apart.
  ASSERT_EQ(run(common + c.string() + " --set system.dt=2e-6").status, 0);
  const std::string da = state_digest(a), db = state_digest(b), dc = state_digest(c);
  ASSERT_EQ(da.size(), 16u);
  EXPECT_EQ(da, db);
  EXPECT_NE(da, dc);
}

TEST(CliRun, DemThreadsOptionKeepsTheBitsAndIsRecorded) {
  const std::string common = "run " + scenes + "/dem_freefall_box.toml --set 'system.group[0].N=800'"
                             " --set 'system.box=[0.012,0.012,0.03]' --set run.until=0.01 --set output.png=false"
                             " --set output.mp4=false --set 'render.size=[32,32]' -o ";
  const fs::path a = fresh_dir("threads_1"), b = fresh_dir("threads_2");
  ASSERT_EQ(run(common + a.string() + " --threads 1").status, 0);
  ASSERT_EQ(run(common + b.string() + " --threads 2").status, 0);
  EXPECT_EQ(state_digest(a), state_digest(b));
  auto text = [](const fs::path& dir) {
    std::ifstream f(dir / "run.json");
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  EXPECT_TRUE(contains(text(a), "\"threads\": 1")) << text(a);
  EXPECT_TRUE(contains(text(b), "\"threads\": 2")) << text(b);
  const Result bad = run(common + fresh_dir("threads_0").string() + " --threads 0");
  EXPECT_NE(bad.status, 0);
  EXPECT_TRUE(contains(bad.output, "--threads")) << bad.output;
}

TEST(CliRun, EffectiveSceneResolvesRelativeFilesSoTheRunFolderReruns) {
  const fs::path a = fresh_dir("rerun_a"), b = fresh_dir("rerun_b");
  const std::string opts = " --set run.until=2e-6 --set output.mp4=false --set 'render.size=[32,32]'";
  ASSERT_EQ(run("run " + scenes + "/dem_vdw_pair.toml -o " + a.string() + opts).status, 0);
  // scenes/dem_vdw_pair.toml names data/vdw_pair.xyz relative to itself.
  const Result r = run("run " + (a / "scene.toml").string() + " -o " + b.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(state_digest(a), state_digest(b));
}

TEST(CliRun, RenderRangeFixesTheColourScaleAndMustNotBeEmpty) {
  const fs::path a = fresh_dir("range_bad"), b = fresh_dir("range_lo"), c = fresh_dir("range_hi");
  const std::string base = "run " + scenes + "/disks_box.toml --set system.box=[20.0,20.0] --set run.until=1.0"
                           " --set sample.exposure=1.0 --set output.mp4=false --set 'render.size=[64,64]' -o ";
  const Result bad = run(base + a.string() + " --set 'render.range=[1.0,1.0]'");
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(contains(bad.output, "render.range")) << bad.output;
  // Every speed below 10: range [10, 20] draws all disks in the colour map's low end,
  // range [0, 1e-3] all in its high end, so the two frames differ.
  ASSERT_EQ(run(base + b.string() + " --set 'render.range=[10.0,20.0]'").status, 0);
  ASSERT_EQ(run(base + c.string() + " --set 'render.range=[0.0,0.001]'").status, 0);
  const auto lo = grainflow::render::read_png((b / "frames/frame_000000.png").string());
  const auto hi = grainflow::render::read_png((c / "frames/frame_000000.png").string());
  ASSERT_EQ(lo.width, hi.width);
  EXPECT_NE(lo.rgba, hi.rgba);
}

// ---- checkpoints and --resume (#12) ------------------------------------------------------

namespace {

// Starts `grainflow ARGS…` in the background, its output thrown away.
pid_t spawn(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    std::vector<char*> argv = {const_cast<char*>(GRAINFLOW_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(GRAINFLOW_EXE, argv.data());
    _exit(127);
  }
  return pid;
}

// Waits until `file` exists (true) or the process ended or 60 s passed (false).
bool wait_for_file(pid_t pid, const fs::path& file) {
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60)) {
    if (fs::exists(file)) return true;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

std::vector<std::string> split_args(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ' ') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

int count_frames(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir / "frames"))
    if (e.path().extension() == ".png") ++n;
  return n;
}

// Runs `scene_args` into a reference folder, then again into a second folder that is
// killed with `signal` once its second checkpoint is written, resumes it, and expects the
// same final state bits, the same stats.csv bytes and the same frames.
void expect_kill_and_resume_match(const std::string& name, const std::string& scene_args, int signal,
                                  const std::string& mp4) {
  const fs::path ref = fresh_dir(name + "_ref"), killed = fresh_dir(name + "_killed");
  const Result r = run(scene_args + " -o " + ref.string());
  ASSERT_EQ(r.status, 0) << r.output;

  auto args = split_args(scene_args);
  args.insert(args.end(), {"-o", killed.string()});
  const pid_t pid = spawn(args);
  ASSERT_GT(pid, 0);
  // Both slots written: at least two checkpoints behind, more frames maybe after them.
  const bool checkpointed = wait_for_file(pid, killed / "checkpoints/checkpoint_0.gfck");
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(checkpointed) << "the run ended before its second checkpoint";
  if (signal == SIGKILL) {
    ASSERT_TRUE(WIFSIGNALED(status)) << status;
    EXPECT_TRUE(contains(read_file(killed / "run.json"), "\"status\": \"running\""));
  } else {
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << status;
    EXPECT_TRUE(contains(read_file(killed / "run.json"), "\"status\": \"interrupted\""));
  }

  const Result resumed = run("run --resume " + killed.string());
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_TRUE(contains(resumed.output, "resuming at")) << resumed.output;
  const std::string run_json = read_file(killed / "run.json");
  EXPECT_TRUE(contains(run_json, "\"status\": \"complete\"")) << run_json;
  EXPECT_TRUE(contains(run_json, "\"resumes\": 1")) << run_json;
  EXPECT_EQ(state_digest(killed), state_digest(ref));
  EXPECT_FALSE(state_digest(ref).empty());
  // Rows continue without a gap or a repeat, to the last bit.
  EXPECT_EQ(read_file(killed / "stats.csv"), read_file(ref / "stats.csv"));
  EXPECT_FALSE(fs::exists(killed / "stats.csv.partial"));
  // So do the particle files, persistent ids included.
  for (const char* file : {"particles.xyz", "particles.lammpstrj"}) {
    if (!fs::exists(ref / file)) continue;
    EXPECT_TRUE(read_file(killed / file) == read_file(ref / file)) << file << " differs after the resume";
    EXPECT_FALSE(fs::exists(killed / (std::string(file) + ".partial"))) << file;
  }
  // The frames continue their numbering and draw the same pictures.
  EXPECT_EQ(count_frames(killed), count_frames(ref));
  for (const auto& e : fs::directory_iterator(ref / "frames"))
    EXPECT_EQ(read_file(killed / "frames" / e.path().filename()), read_file(e.path())) << e.path().filename();
  // One video of every frame.
  EXPECT_TRUE(fs::exists(killed / mp4));
  EXPECT_FALSE(fs::exists(killed / (mp4 + ".partial")));
  EXPECT_EQ(grainflow::render::test::decodable_frames(killed / mp4), count_frames(ref));
}

}  // namespace

TEST(CliRun, KilledEdStreamResumesToTheSameBits) {
  // The dispenser, the filter and the obstacle, with a checkpoint every two frames.
  expect_kill_and_resume_match("resume_ed",
                               "run " + scenes + "/obstacle_quick.toml --set run.until=160 --set sample.exposure=8 "
                               "--set output.checkpoint_every=16 --set render.size=[160,96] --set output.particles=true "
                               "--set output.lammps_dump=true",
                               SIGKILL, "obstacle_quick.mp4");
}

TEST(CliRun, KilledPhasedCouetteRunResumesAcrossPhasesToTheSameBits) {
  // Moving thermal walls, a flip obstacle, the thermostat and four phases, one before the
  // second checkpoint (t = 20), where the run is killed, three after it: the resumed run
  // crosses them. stats.csv records the phase and the values; the captions say them.
  const fs::path dir = fresh_dir("resume_phases_scene");
  const fs::path scene = dir / "phased.toml";
  write_file(scene, R"([run]
engine = "ed"
until = 120.0
seed = 4
[system]
box = [60.0, 60.0]
area_fraction = 0.5
kT = 0.02
tau_tc = 1e-4
tau_tc_step = 1e-4
[boundary]
periodic = [true, false]
[boundary.walls]
kind = "noslip_thermal"
U = [-0.1, 0.1]
[boundary.obstacle]
D = 10.0
x = 30.0
y = 30.0
kind = "noslip_flip"
[thermostat]
tau = 3.48
tau_v = 12.0
bin = 6.0
[[phase]]
at = 5.0
thermostat = false
[[phase]]
at = 25.0
label = "inelastic"
e = 0.9
obstacle_r = 0.9
[[phase]]
at = 70.0
thermostat = true
thermostat_T = 0.03
obstacle_kind = "noslip_thermal"
[[phase]]
at = 95.0
e = 1.0
[sample]
exposure = 8.0
bins = [10, 10]
[render]
size = [160, 120]
)");
  expect_kill_and_resume_match("resume_phases", "run " + scene.string() + " --set output.checkpoint_every=10",
                               SIGKILL, "phased.mp4");
  // The values in effect at the end of each row: rows at t = 32 and t = 120.
  std::istringstream csv(read_file(fs::path(GRAINFLOW_TEST_OUT) / "cli" / "resume_phases_killed" / "stats.csv"));
  std::string header, line;
  std::getline(csv, header);
  ASSERT_TRUE(contains(header, ",phase,e,obstacle_r,obstacle_kind,thermostat_on,thermostat_T,")) << header;
  auto field = [](const std::string& row, std::size_t k) {
    std::size_t b = 0;
    for (std::size_t i = 0; i < k; ++i) b = row.find(',', b) + 1;
    return row.substr(b, row.find(',', b) - b);
  };
  const std::size_t phase_col = std::size_t(std::count(header.begin(), header.begin() + long(header.find(",phase,")) + 1, ','));
  std::map<std::string, std::string> at;
  while (std::getline(csv, line)) {
    std::string v;
    for (std::size_t k = 0; k < 6; ++k) v += field(line, phase_col + k) + " ";
    at[field(line, 0)] = v;
  }
  // obstacle_kind: 2 the flip of the scene, 1 the thermal surface phase 3 switches to.
  EXPECT_EQ(at["32"], "2 0.9 0.9 2 0 0.02 ");
  EXPECT_EQ(at["120"], "4 1 0.9 1 1 0.03 ");
}

TEST(CliRun, InterruptedDemBedResumesToTheSameBits) {
  // Spheres in contact under gravity; SIGTERM finishes the files, --resume continues them.
  expect_kill_and_resume_match("resume_dem",
                               "run " + scenes + "/dem_freefall_box.toml --set system.group[0].N=800 "
                               "--set system.box=[0.012,0.012,0.03] --set run.until=0.02 --set sample.exposure=0.001 "
                               "--set output.checkpoint_every=0.002 --set render.size=[96,96] --threads 1",
                               SIGTERM, "dem_freefall_box.mp4");
}

TEST(CliRun, ResumeRefusesWhatItCannotContinue) {
  const fs::path out = fresh_dir("resume_refusals");
  const std::string scene = "run " + scenes + "/disks_box.toml --set run.until=20 --set output.checkpoint_every=5 "
                            "--set render.size=[64,64] --set output.mp4=false -o " + out.string();
  ASSERT_EQ(run(scene).status, 0);
  const std::string digest = state_digest(out);
  // A complete run has nothing left to do...
  Result r = run("run --resume " + out.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "run.until")) << r.output;
  // ...and keys that decide the state cannot change on resume.
  r = run("run --resume " + out.string() + " --set system.kT=0.05 --set run.until=40");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "system.kT cannot change on --resume")) << r.output;
  EXPECT_TRUE(contains(r.output, "run.until")) << r.output;
  // An edited scene.toml is another scene.
  const std::string original = read_file(out / "scene.toml");
  std::string edited = original;
  const auto k = edited.find("kT = ");
  ASSERT_NE(k, std::string::npos);
  edited.replace(k, 5, "kT = 0.5 #");
  write_file(out / "scene.toml", edited);
  r = run("run --resume " + out.string() + " --set run.until=40");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "another scene")) << r.output;
  write_file(out / "scene.toml", original);
  // Damaged checkpoints are refused with the reason, and the folder is left as it was.
  const std::string stats = read_file(out / "stats.csv");
  for (const char* slot : {"checkpoints/checkpoint_0.gfck", "checkpoints/checkpoint_1.gfck"}) {
    std::string bytes = read_file(out / slot);
    ASSERT_GT(bytes.size(), 100u);
    bytes[bytes.size() / 2] ^= 0x10;
    std::ofstream(out / slot, std::ios::binary | std::ios::trunc) << bytes;
  }
  r = run("run --resume " + out.string() + " --set run.until=40");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "checksum")) << r.output;
  EXPECT_EQ(read_file(out / "stats.csv"), stats);
  EXPECT_EQ(state_digest(out), digest);
  // Not a run folder at all.
  r = run("run --resume " + fresh_dir("resume_nothing").string());
  EXPECT_EQ(r.status, 2) << r.output;
}

TEST(CliRun, ACompleteRunIsExtendedByResumeToTheSameBits) {
  const std::string common = "run " + scenes + "/disks_box.toml --set render.size=[64,64] --set output.mp4=false "
                             "--set output.checkpoint_every=10 ";
  const fs::path direct = fresh_dir("extend_direct"), extended = fresh_dir("extend_resumed");
  ASSERT_EQ(run(common + "--set run.until=40 -o " + direct.string()).status, 0);
  ASSERT_EQ(run(common + "--set run.until=20 -o " + extended.string()).status, 0);
  const Result r = run("run --resume " + extended.string() + " --set run.until=40");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(state_digest(extended), state_digest(direct));
  EXPECT_EQ(read_file(extended / "stats.csv"), read_file(direct / "stats.csv"));
  EXPECT_EQ(count_frames(extended), count_frames(direct));
}

TEST(CliRun, MaxStepsStopsAtAReproduciblePointAndResumes) {
  const std::string common = "run " + scenes + "/disks_box.toml --set render.size=[64,64] --set output.mp4=false "
                             "--set run.until=30 ";
  const fs::path direct = fresh_dir("max_steps_direct"), stopped = fresh_dir("max_steps_stopped");
  ASSERT_EQ(run(common + "-o " + direct.string()).status, 0);
  const Result r = run(common + "--set run.max_steps=200000 -o " + stopped.string());
  EXPECT_EQ(r.status, 130) << r.output;
  EXPECT_TRUE(contains(r.output, "run.max_steps")) << r.output;
  EXPECT_TRUE(contains(read_file(stopped / "run.json"), "\"status\": \"interrupted\""));
  EXPECT_TRUE(fs::exists(stopped / "checkpoints/checkpoint_1.gfck"));
  const Result resumed = run("run --resume " + stopped.string() + " --set run.max_steps=0");
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_EQ(state_digest(stopped), state_digest(direct));
  EXPECT_EQ(read_file(stopped / "stats.csv"), read_file(direct / "stats.csv"));
}

TEST(CliRun, EdStartsFromTheParticlesOfAnEarlierRun) {
  const std::string common = "run " + scenes + "/disks_box.toml --set render.size=[64,64] --set output.mp4=false "
                             "--set run.until=10 --set output.particles=true ";
  const fs::path first = fresh_dir("from_file_first"), second = fresh_dir("from_file_second");
  ASSERT_EQ(run(common + "-o " + first.string()).status, 0);
  const std::string file = (first / "particles.xyz").string();
  const Result r = run(common + "--set system.initial.kind=file --set system.initial.file=" + file + " -o " +
                       second.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "system.area_fraction is not used")) << r.output;
  // The second run's first frame is the first run's last one: ids, positions, velocities,
  // spins and masses at full precision (only the clock starts again at 0).
  auto frames = [](const fs::path& p) {
    std::vector<std::string> out;
    std::ifstream in(p);
    std::string count, header, line;
    while (std::getline(in, count) && std::getline(in, header)) {
      std::string body;
      for (long k = std::stol(count); k > 0 && std::getline(in, line); --k) body += line + "\n";
      out.push_back(body);
    }
    return out;
  };
  const auto a = frames(first / "particles.xyz"), b = frames(second / "particles.xyz");
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(a.back(), b.front());
  // What the file cannot give is refused with the reason.
  Result bad = run(common + "--set system.initial.kind=file --set system.initial.file=" + file +
                   " --set system.initial.frame=99 -o " + fresh_dir("from_file_frame").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, "holds 6 frame(s)")) << bad.output;
  bad = run(common + "--set system.initial.kind=file --set system.initial.file=" + file +
            " --set system.box=[50,50] -o " + fresh_dir("from_file_box").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, "the file's box")) << bad.output;
  bad = run(common + "--set system.initial.kind=file -o " + fresh_dir("from_file_none").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, "needs system.initial.file")) << bad.output;
}

TEST(CliRun, MapColourBarsStayFixedForTheWholeRunByDefault) {
  // One density panel: a strip right of the map holds only its colour bar and ticks.
  // With the default range_mode = "run" they are the same in every frame after the first
  // exposure; with "frame" they follow each frame's percentiles.
  auto bar_strip = [](const fs::path& png) {
    const grainflow::render::Image im = grainflow::render::read_png(png);
    std::string strip;
    for (int y = im.height / 5; y < 17 * im.height / 20; ++y)
      for (int x = 13 * im.width / 20; x < 17 * im.width / 20; ++x)
        strip.append(reinterpret_cast<const char*>(im.pixel(x, y)), 4);
    return strip;
  };
  const std::string common = "run " + scenes + "/disks_box.toml --set render.size=[320,200] --set output.mp4=false "
                             "--set run.until=12 --set 'render.panels=[\"density\"]' ";
  const fs::path stable = fresh_dir("ranges_run"), moving = fresh_dir("ranges_frame");
  ASSERT_EQ(run(common + "-o " + stable.string()).status, 0);
  ASSERT_EQ(run(common + "--set render.range_mode=frame -o " + moving.string()).status, 0);
  const std::string first = "frames/frame_000001.png", last = "frames/frame_000006.png";
  EXPECT_TRUE(bar_strip(stable / first) == bar_strip(stable / last));
  EXPECT_FALSE(bar_strip(moving / first) == bar_strip(moving / last));
  EXPECT_FALSE(bar_strip(stable / first) == std::string(bar_strip(stable / first).size(), '\xff'));  // not blank
  // A fixed range must belong to a panel that is drawn.
  const Result bad = run(common + "--set render.ranges.temperature=[0.01,0.03] -o " + fresh_dir("ranges_bad").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, "render.panels has no temperature panel")) << bad.output;
}

TEST(CliRun, StreamlinesMayBeSeenMovingWithTheStream) {
  // obstacle_quick's first exposure: far downstream the mean velocity is the stream's U =
  // 0.2. On the streamlines panel (bottom left of 2 × 2, range fixed to [0, 0.32]) that
  // reads 0.6 of the map, green, in the obstacle's frame; moving with the stream,
  // |<v> − U| ≈ 0 there: the map's dark end. Counted: of the map's pixels (not the white
  // streamlines) in a strip of the panel 150–185 σ downstream, mid-height, the dark ones.
  const std::string common = "run " + scenes + "/obstacle_quick.toml --set render.size=[640,360] "
                             "--set output.mp4=false --set run.until=24 ";
  const fs::path obstacle = fresh_dir("streamlines_obstacle"), stream = fresh_dir("streamlines_stream");
  ASSERT_EQ(run(common + "-o " + obstacle.string()).status, 0);
  ASSERT_EQ(run(common + "--set render.streamlines_frame=stream -o " + stream.string()).status, 0);
  auto dark = [](const fs::path& png) {
    const grainflow::render::Image im = grainflow::render::read_png(png);
    int n = 0, all = 0;
    for (int y = 70 * im.height / 100; y < 80 * im.height / 100; ++y)
      for (int x = 29 * im.width / 100; x < 35 * im.width / 100; ++x) {
        const auto* c = im.pixel(x, y);
        if (c[0] > 150) continue;  // a streamline
        ++all;
        n += c[1] < 80;
      }
    return all > 50 ? double(n) / all : -1.0;
  };
  const std::string frame = "frames/frame_000001.png";
  const double in_obstacle_frame = dark(obstacle / frame), with_stream = dark(stream / frame);
  EXPECT_GE(in_obstacle_frame, 0.0);
  EXPECT_LT(in_obstacle_frame, 0.05);
  EXPECT_GT(with_stream, 0.5);
  // Moving with the stream needs a panel that shows the flow.
  const Result bad = run("run " + scenes + "/disks_box.toml --set render.streamlines_frame=stream "
                         "--set 'render.panels=[\"density\"]' -o " + fresh_dir("streamlines_bad").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, "has no streamlines or velocity panel")) << bad.output;
}

// The thermostat of seed 003 ch. 6 ([thermostat]): disks_box with it completes, stats.csv
// gains its columns (events per row, power injected), run.json its totals, and a run
// extended by --resume gives the same bits and rows (its random stream, bins and the stats
// window are in the checkpoint). Its keys are validated before any folder exists.
TEST(CliRun, DisksBoxWithAThermostatAddsItsColumnsAndResumesToTheSameBits) {
  // Started at half T_th: the thermostat heats, so the power is positive.
  const std::string common = "run " + scenes + "/disks_box.toml --set system.box=[30.0,30.0] --set system.kT=0.01 "
                             "--set thermostat.T=0.02 --set thermostat.tau=1.0 --set thermostat.tau_v=4.0 "
                             "--set thermostat.bin=5.0 --set render.size=[64,64] --set output.mp4=false "
                             "--set output.png=false --set output.checkpoint_every=4 ";
  const fs::path direct = fresh_dir("thermostat_direct"), extended = fresh_dir("thermostat_extended");
  const Result r = run(common + "--set run.until=12 -o " + direct.string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream csv(direct / "stats.csv");
  std::string header, row;
  std::getline(csv, header);
  std::vector<std::string> names;
  for (std::size_t a = 0, b; a <= header.size(); a = b + 1) {
    b = header.find(',', a);
    if (b == std::string::npos) b = header.size();
    names.push_back(header.substr(a, b - a));
  }
  const auto col = [&](const char* n) { return std::size_t(std::find(names.begin(), names.end(), n) - names.begin()); };
  ASSERT_LT(col("thermostat_events"), names.size()) << header;
  ASSERT_LT(col("thermostat_power"), names.size()) << header;
  int rows = 0;
  while (std::getline(csv, row)) {
    std::vector<double> v;
    for (std::size_t a = 0, b; a <= row.size(); a = b + 1) {
      b = row.find(',', a);
      if (b == std::string::npos) b = row.size();
      v.push_back(std::atof(row.substr(a, b - a).c_str()));
    }
    ASSERT_EQ(v.size(), names.size()) << row;
    if (v[0] == 0.0) continue;  // the row at t = 0 covers no window
    ++rows;
    // N ≈ 745 disks, τ = 1, rows every 2: ≈ 1490 events a row.
    EXPECT_GT(v[col("thermostat_events")], 1000.0) << row;
    if (rows == 1) {
      EXPECT_GT(v[col("thermostat_power")], 0.0) << row;
    }
  }
  EXPECT_EQ(rows, 6);
  EXPECT_TRUE(contains(read_file(direct / "run.json"), "\"thermostat_events\": ")) << read_file(direct / "run.json");
  ASSERT_EQ(run(common + "--set run.until=6 -o " + extended.string()).status, 0);
  const Result resumed = run("run --resume " + extended.string() + " --set run.until=12");
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_EQ(state_digest(extended), state_digest(direct));
  EXPECT_EQ(read_file(extended / "stats.csv"), read_file(direct / "stats.csv"));
  // Another kind is another trajectory.
  const fs::path dual = fresh_dir("thermostat_dual");
  ASSERT_EQ(run(common + "--set run.until=12 --set 'thermostat.kind=\"dual\"' -o " + dual.string()).status, 0);
  EXPECT_NE(state_digest(dual), state_digest(direct));
}

TEST(CliRun, ThermostatKeysAreCheckedBeforeTheFolderExists) {
  struct Bad {
    std::string set, needle;
  };
  for (const Bad& b : {Bad{"thermostat.bin=150.0", "thermostat.bin = 150.0 is larger than the box"},
                       Bad{"thermostat.bin=0.5", "a bin must hold disks"},
                       Bad{"thermostat.tau=0.0", "thermostat.tau"},
                       Bad{"thermostat.tau_v=-1.0", "thermostat.tau_v"},
                       Bad{"thermostat.T=0.0", "thermostat.T"},
                       Bad{"thermostat.kind=\\\"triple\\\"", "\"single\" | \"dual\" | \"global\""}}) {
    const fs::path out = fresh_dir("thermostat_refused");
    const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() + " --set \"" + b.set + "\"");
    EXPECT_EQ(r.status, 2) << b.set << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, b.needle)) << b.set << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << b.set;
  }
}

namespace {

// The frame rate a run's MP4 plays at, as an independent reader sees it.
double video_fps(const fs::path& mp4) {
  const auto d = grainflow::render::test::decode(mp4);
  return d.duration_s > 0 ? double(d.frames.size()) / d.duration_s : 0.0;
}

}  // namespace

TEST(CliRun, VideoLastsAboutVideoSecondsUnlessTheSceneGivesTheFrameRate) {
  // 41 frames (t = 0, 0.5, …, 20) and output.video_seconds = 4: 10 frames/s, written into
  // the effective scene so that a resume keeps it.
  const std::string small = " --set system.box=[12.0,12.0] --set run.until=20.0 --set sample.exposure=0.5"
                            " --set render.size=[64,64] --set output.video_seconds=4";
  const fs::path out = fresh_dir("run_auto_fps");
  const Result r = run("run " + scenes + "/disks_box.toml -o " + out.string() + small);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(read_file(out / "scene.toml"), "fps = 10  #")) << read_file(out / "scene.toml");
  EXPECT_NEAR(video_fps(out / "disks_box.mp4"), 10.0, 0.3);
  // A rate the scene gives is kept.
  const fs::path given = fresh_dir("run_given_fps");
  const Result r2 = run("run " + scenes + "/disks_box.toml -o " + given.string() + small + " --set output.fps=25");
  ASSERT_EQ(r2.status, 0) << r2.output;
  EXPECT_NEAR(video_fps(given / "disks_box.mp4"), 25.0, 0.5);
  // Long runs are capped at 60 frames/s, short ones get at least 1.
  const fs::path slow = fresh_dir("run_slow_fps");
  const Result r3 = run("run " + scenes + "/disks_box.toml -o " + slow.string() + small +
                        " --set output.video_seconds=1000");
  ASSERT_EQ(r3.status, 0) << r3.output;
  EXPECT_TRUE(contains(read_file(slow / "scene.toml"), "fps = 1  #")) << read_file(slow / "scene.toml");
  EXPECT_NE(run("run " + scenes + "/disks_box.toml -o " + fresh_dir("run_bad_seconds").string() + small +
                " --set output.video_seconds=0")
                .status,
            0);
}

// `grainflow plot`: a stats.csv drawn with two --y, log y; the errors a user meets.
TEST(CliPlot, DrawsStatsColumnsAndNamesWhatIsWrong) {
  const fs::path dir = fresh_dir("plot_run"), png = fresh_dir("plot_png");
  ASSERT_EQ(run("run " + scenes + "/disks_box.toml --set run.until=4 --set output.png=false --set output.mp4=false "
                "--set sample.exposure=0.5 -o " + dir.string()).status, 0);
  fs::create_directories(png);
  const std::string stats = (dir / "stats.csv").string();
  const std::string out = (png / "kT.png").string();
  Result r = run("plot " + stats + " --x time --y kT --y pressure --log-y --title 'box' --size 320 240 -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto img = grainflow::render::read_png(out);
  EXPECT_EQ(img.width, 320);
  EXPECT_EQ(img.height, 240);
  // Not overwritten without --force; replaced with it.
  r = run("plot " + stats + " --y kT -o " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "--force")) << r.output;
  EXPECT_EQ(run("plot " + stats + " --y kT --force -o " + out).status, 0);
  // An unknown column: the closest one and the list.
  r = run("plot " + stats + " --y kt -o " + (png / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "did you mean 'kT'?")) << r.output;
  EXPECT_TRUE(contains(r.output, "columns: time, collisions")) << r.output;
  // A log axis and values ≤ 0 (the total momentum is zero to round-off).
  r = run("plot " + stats + " --y momentum_x --log-y -o " + (png / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "logarithmic")) << r.output;
  // An error column for each --y, and none negative.
  r = run("plot " + stats + " --y kT --y pressure --y-err kT -o " + (png / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "one per --y")) << r.output;
  r = run("plot " + stats + " --y kT --y-err momentum_x -o " + (png / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "error bars ≥ 0")) << r.output;
  // Empty files and a header without rows.
  std::ofstream(png / "empty.csv");
  std::ofstream(png / "header.csv") << "time,kT\n";
  std::ofstream(png / "bad.csv") << "time,kT\n1,0.5\n2,abc\n";
  r = run("plot " + (png / "empty.csv").string() + " --y kT -o " + (png / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "is empty")) << r.output;
  r = run("plot " + (png / "header.csv").string() + " --y kT -o " + (png / "x.png").string());
  EXPECT_TRUE(contains(r.output, "no rows")) << r.output;
  r = run("plot " + (png / "bad.csv").string() + " --y kT -o " + (png / "x.png").string());
  EXPECT_TRUE(contains(r.output, "bad.csv:3")) << r.output;
  EXPECT_FALSE(fs::exists(png / "x.png"));
}

// --rows joins a sweep's study.csv files into one table, --group splits it by a column.
TEST(CliPlot, RowsAndGroupDrawASweep) {
  const fs::path dir = fresh_dir("plot_rows");
  int k = 0;
  for (double r : {0.97, 0.87})
    for (double tau : {1.0, 3.48, 10.0}) {
      fs::create_directories(dir / std::to_string(k));
      std::ofstream(dir / std::to_string(k++) / "study.csv")
          << "r,r_err,tau_th,tau_th_err,T_th_needed,T_th_needed_err\n"
          << r << ",nan," << tau << ",nan," << 0.02 + (1 - r * r) * tau * 0.02 << ",0.0002\n";
    }
  std::string files;
  for (int i = 0; i < k; ++i) files += (dir / std::to_string(i) / "study.csv").string() + " ";
  const Result r = run("plot --rows " + files + "--x tau_th --y T_th_needed --y-err T_th_needed_err --group r "
                       "--log-x --points -o " + (dir / "sweep.png").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "2 series")) << r.output;
  std::ofstream(dir / "other.csv") << "a,b\n1,2\n";
  const Result bad = run("plot --rows " + files + (dir / "other.csv").string() + " --x tau_th --y T_th_needed -o " +
                         (dir / "x.png").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(contains(bad.output, "other columns")) << bad.output;
}

// The homogeneous cooling study, scaled down (N = 1024): study.json, .csv and .png in the
// run folder; an interrupted run resumed gives the same study.csv.
TEST(CliStudy, HaffCoolingWritesItsResultAndResumesToTheSameNumbers) {
  const fs::path eq = fresh_dir("study_eq"), direct = fresh_dir("study_direct"), stopped = fresh_dir("study_stopped");
  const std::string small = " --set system.box=[35.17,35.17] ";
  ASSERT_EQ(run("run " + scenes + "/studies/haff_equilibrium.toml" + small + "--set system.N=1024 --set run.until=5 --set sample.exposure=5 -o " +
                eq.string()).status, 0);
  const std::string common = "run " + scenes + "/studies/haff_r087.toml" + small + "--set run.until=30 "
                             "--set study.tolerance=0.1 --set system.initial.file=\"" +
                             (eq / "particles.xyz").string() + "\" ";
  Result r = run(common + "-o " + direct.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string json = read_file(direct / "study.json");
  EXPECT_TRUE(contains(json, "\"study\": \"haff_cooling\"")) << json;
  EXPECT_TRUE(contains(json, "\"early_rate_ratio\"")) << json;
  EXPECT_TRUE(contains(json, "\"passed\": true")) << json;
  EXPECT_TRUE(fs::exists(direct / "study.png"));
  EXPECT_GT(grainflow::render::read_png(direct / "study.png").width, 0);
  r = run(common + "--set run.max_steps=8000 -o " + stopped.string());
  EXPECT_EQ(r.status, 130) << r.output;
  r = run("run --resume " + stopped.string() + " --set run.max_steps=0");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read_file(stopped / "study.csv"), read_file(direct / "study.csv"));
  // --force removes what the study wrote, as it claimed.
  r = run(common + "--set run.until=0.1 --force -o " + direct.string());
  EXPECT_NE(r.status, 0);  // two stats rows cannot be fitted: says so
  EXPECT_TRUE(contains(r.output, "haff_cooling study")) << r.output;
}

// The shipped Couette study scene, scaled down (24 × 24, U = ∓0.2, blocks of 100 τ after
// 300 τ): a run stopped part-way (its exposures' profiles are in the checkpoint) and resumed
// writes the same study.csv as the run straight through.
TEST(CliStudy, CouetteStudyResumesToTheSameNumbers) {
  const fs::path direct = fresh_dir("couette_direct"), stopped = fresh_dir("couette_stopped");
  const std::string common = "run " + scenes + "/studies/couette.toml --set system.box=[24.0,24.0] "
                             "--set system.area_fraction=0.5 --set \"boundary.walls.U=[-0.2, 0.2]\" "
                             "--set run.until=700 --set sample.exposure=100 --set output.stats_every=50 "
                             "--set sample.bins=[2,8] --set study.skip=300 --set output.checkpoint_every=100 ";
  Result r = run(common + "-o " + direct.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(read_file(direct / "study.json"), "\"study\": \"couette\"")) << r.output;
  r = run(common + "--set run.max_steps=175000 -o " + stopped.string());
  EXPECT_EQ(r.status, 130) << r.output;
  r = run("run --resume " + stopped.string() + " --set run.max_steps=0");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read_file(stopped / "study.csv"), read_file(direct / "study.csv"));
}

TEST(CliStudy, StudyKeysAreCheckedBeforeTheFolderExists) {
  const fs::path dir = fresh_dir("study_keys");
  Result r = run("run " + scenes + "/studies/haff_r087.toml --set system.e=1.0 -o " + dir.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "does not cool")) << r.output;
  r = run("run " + scenes + "/studies/thermostat_r097.toml --set study.early=0.2 -o " + dir.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.output, "haff_cooling study")) << r.output;
  r = run("run " + scenes + "/dem_couette.toml --set study.kind=\"haff_cooling\" -o " + dir.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}
