// `grainflow render` of other codes' dumps as a researcher meets them (a LAMMPS `fix pour`
// dump that starts empty and is still being written; frame ranges; camera; field planes;
// legends) and `grainflow diff` of two run folders, end to end through the executable.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "render/image/compare.hpp"
#include "render/image/image.hpp"
#include "render/output/png_io.hpp"
#include "tests/render/mp4_test_support.hpp"
#include "tests/scenes/cli_support.hpp"

namespace fs = std::filesystem;
using grainflow::render::Image;
using grainflow::render::read_png;

namespace {

const std::string data = GRAINFLOW_TEST_DATA;
const std::string scenes = GRAINFLOW_SCENES_DIR;
const std::string pour = data + "/particles/lammps_pour_still_running.lammpstrj";

bool saturated(const std::uint8_t* p) {
  const int mx = std::max({p[0], p[1], p[2]}), mn = std::min({p[0], p[1], p[2]});
  return mx - mn > 40;
}

// The tallest run of saturated (colour-map, not grey ink) pixels in one column of
// [x0, x1): a vertical colour bar is one.
int tallest_colour_column(const Image& im, int x0, int x1) {
  int best = 0;
  for (int x = x0; x < x1; ++x) {
    int run = 0;
    for (int y = 0; y < im.height; ++y) {
      run = saturated(im.pixel(x, y)) ? run + 1 : 0;
      best = std::max(best, run);
    }
  }
  return best;
}

// Dark (text) pixels in the rows [y0, y1).
int ink_pixels(const Image& im, int y0, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < im.width; ++x) n += im.pixel(x, y)[0] < 100 && im.pixel(x, y)[1] < 100;
  return n;
}

// The acceptance case of issue 14: the pour dump (tests/data/particles/
// lammps_pour_still_running.in) has an empty first frame and ends inside its 7th frame.
TEST(CliRender, PourStillBeingWrittenRendersItsCompleteFrames) {
  const fs::path out = fresh_dir("render_pour");
  const Result r = run("render " + pour + " -o " + out.string() + " --size 320 240 --dt 0.001");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "colour by speed")) << r.output;  // the empty first frame kept vx vy vz
  EXPECT_TRUE(contains(r.output, "warning")) << r.output;
  EXPECT_TRUE(contains(r.output, "ends inside frame 6")) << r.output;
  EXPECT_TRUE(contains(r.output, "lammps_pour_still_running.lammpstrj:172:")) << r.output;
  for (int k = 0; k < 6; ++k) EXPECT_TRUE(fs::exists(out / ("frames/frame_00000" + std::to_string(k) + ".png"))) << k;
  EXPECT_FALSE(fs::exists(out / "frames/frame_000006.png"));
  ASSERT_TRUE(fs::exists(out / "lammps_pour_still_running.mp4"));
  EXPECT_EQ(grainflow::render::test::decodable_frames(out / "lammps_pour_still_running.mp4"), 6);

  // Frame 5 (24 spheres, coloured by speed): a colour bar right of the box, a caption
  // under it; the bare picture has neither.
  const Image im = read_png(out / "frames/frame_000005.png");
  EXPECT_GT(tallest_colour_column(im, im.width * 56 / 100, im.width), im.height / 2);
  EXPECT_GT(ink_pixels(im, im.height * 96 / 100, im.height), 40);
  const fs::path bare = fresh_dir("render_pour_bare");
  ASSERT_EQ(run("render " + pour + " -o " + bare.string() + " --size 320 240 --no-annotations --no-mp4").status, 0);
  const Image plain = read_png(bare / "frames/frame_000005.png");
  EXPECT_GT(ink_pixels(im, im.height * 96 / 100, im.height), ink_pixels(plain, plain.height * 96 / 100, plain.height) + 40);
}

TEST(CliRender, FrameRangeAndEveryKeepTheFilesNumbering) {
  const fs::path out = fresh_dir("render_range");
  const Result r = run("render " + pour + " -o " + out.string() + " --size 64 48 --first 1 --last 5 --every 2");
  ASSERT_EQ(r.status, 0) << r.output;
  for (int k : {1, 3, 5}) EXPECT_TRUE(fs::exists(out / ("frames/frame_00000" + std::to_string(k) + ".png"))) << k;
  for (int k : {0, 2, 4, 6}) EXPECT_FALSE(fs::exists(out / ("frames/frame_00000" + std::to_string(k) + ".png"))) << k;
  EXPECT_FALSE(contains(r.output, "warning")) << r.output;  // --last stops before the cut frame
  EXPECT_EQ(grainflow::render::test::decodable_frames(out / "lammps_pour_still_running.mp4"), 3);

  const fs::path beyond = fresh_dir("render_range_beyond");
  const Result b = run("render " + pour + " -o " + beyond.string() + " --first 9");
  EXPECT_EQ(b.status, 2);
  EXPECT_TRUE(contains(b.output, "holds only 6 complete frames")) << b.output;
  EXPECT_FALSE(fs::exists(beyond));
  EXPECT_EQ(run("render " + pour + " -o " + beyond.string() + " --first 3 --last 2").status, 2);
}

TEST(CliRender, CategoriesGetALegendInDistinctColours) {
  const fs::path out = fresh_dir("render_legend");
  const std::string file = data + "/particles/extended_two_frames.xyz";  // species Cu and Ag
  ASSERT_EQ(run("render " + file + " -o " + out.string() + " --size 320 240 --color-by type --no-mp4").status, 0);
  const Image im = read_png(out / "frames/frame_000000.png");
  // The legend's swatches: flat tab10 colours 1 (orange) and 2 (green) right of the box.
  auto count = [&](std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = im.width * 60 / 100; x < im.width; ++x) {
        const auto* p = im.pixel(x, y);
        n += std::abs(p[0] - r) < 3 && std::abs(p[1] - g) < 3 && std::abs(p[2] - b) < 3;
      }
    return n;
  };
  EXPECT_GT(count(0xff, 0x7f, 0x0e), 60);
  EXPECT_GT(count(0x2c, 0xa0, 0x2c), 60);
}

TEST(CliRender, CameraZoomTargetAndDistanceMoveTheView) {
  const std::string base = "render " + pour + " --size 96 72 --first 5 --last 5 --no-mp4 --no-annotations -o ";
  const fs::path d0 = fresh_dir("render_cam0"), d1 = fresh_dir("render_cam1"), d2 = fresh_dir("render_cam2"),
                 d3 = fresh_dir("render_cam3");
  ASSERT_EQ(run(base + d0.string()).status, 0);
  ASSERT_EQ(run(base + d1.string() + " --zoom 2").status, 0);
  ASSERT_EQ(run(base + d2.string() + " --target 3 3 1").status, 0);
  ASSERT_EQ(run(base + d3.string() + " --distance 60").status, 0);
  const Image a = read_png(d0 / "frames/frame_000005.png");
  for (const auto& d : {d1, d2, d3})
    EXPECT_GT(grainflow::render::compare_images(a, read_png(d / "frames/frame_000005.png")).fraction_over, 0.05) << d;
  // Far away, the box covers fewer pixels.
  auto non_white = [](const Image& im) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) n += im.pixel(x, y)[0] < 250;
    return n;
  };
  EXPECT_LT(non_white(read_png(d3 / "frames/frame_000005.png")), non_white(a));
  EXPECT_GT(non_white(read_png(d1 / "frames/frame_000005.png")), non_white(a));
  const Result flat = run("render " + data + "/particles/lammps_scaled_2d.lammpstrj -o " +
                          fresh_dir("render_cam_2d").string() + " --distance 5");
  EXPECT_EQ(flat.status, 2);
  EXPECT_TRUE(contains(flat.output, "--distance is for 3D")) << flat.output;
  EXPECT_EQ(run("render " + pour + " -o " + fresh_dir("render_cam_zero").string() + " --zoom 0").status, 2);
}

TEST(CliRender, FieldPanelsOfA3DFileTakeAPlaneAndASlab) {
  const std::string base = "render " + pour + " --size 160 120 --first 5 --last 5 --no-mp4 --panels density --bins 6 6 -o ";
  const fs::path xz = fresh_dir("render_plane_xz"), xy = fresh_dir("render_plane_xy"), slab = fresh_dir("render_slab");
  ASSERT_EQ(run(base + xz.string()).status, 0);  // default for 3D: xz, the vertical plane
  ASSERT_EQ(run(base + xy.string() + " --plane xy").status, 0);
  ASSERT_EQ(run(base + slab.string() + " --slab 0 1.5").status, 0);
  const Image a = read_png(xz / "frames/frame_000005.png");
  // The box is 6 × 6 × 12: the xz plane is twice as tall as wide, the xy plane square.
  EXPECT_GT(grainflow::render::compare_images(a, read_png(xy / "frames/frame_000005.png")).fraction_over, 0.05);
  EXPECT_GT(grainflow::render::compare_images(a, read_png(slab / "frames/frame_000005.png")).fraction_over, 0.01);
  const Result flat = run("render " + data + "/particles/lammps_scaled_2d.lammpstrj -o " +
                          fresh_dir("render_plane_2d").string() + " --panels density --plane xz");
  EXPECT_EQ(flat.status, 2);
  EXPECT_TRUE(contains(flat.output, "2D file has only the xy plane")) << flat.output;
  EXPECT_EQ(run("render " + pour + " -o " + fresh_dir("render_plane_bad").string() + " --panels density --slab 2 1").status, 2);
  EXPECT_EQ(run("render " + pour + " -o " + fresh_dir("render_plane_nopanels").string() + " --plane xy").status, 2);
}

TEST(CliRender, MapRangesAreFixedOrKeptFromTheFirstFrame) {
  const std::string base = "render " + pour + " --size 160 120 --first 2 --last 5 --no-mp4 --panels density --bins 4 4 -o ";
  const fs::path fixed = fresh_dir("render_map_fixed"), run_mode = fresh_dir("render_map_run");
  ASSERT_EQ(run(base + fixed.string() + " --map-range density=0,0.2").status, 0);
  ASSERT_EQ(run(base + run_mode.string()).status, 0);
  // A fixed range for a panel that is not drawn, or a non-map panel, is refused.
  const Result bad = run(base + fresh_dir("render_map_bad").string() + " --map-range temperature=0,1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(contains(bad.output, "no such panel is drawn")) << bad.output;
  EXPECT_EQ(run(base + fresh_dir("render_map_bad2").string() + " --map-range density=1,0").status, 2);
  EXPECT_EQ(run(base + fresh_dir("render_map_bad3").string() + " --map-range density").status, 2);
  // Between frames 3 and 4 (20 spheres each, the last ones still falling) the maps change
  // but the bars — same range — do not: the bar's pixels right of the map are the same.
  for (const auto& d : {fixed, run_mode}) {
    const Image f3 = read_png(d / "frames/frame_000003.png"), f4 = read_png(d / "frames/frame_000004.png");
    int bar_changed = 0;
    for (int y = 0; y < f3.height * 9 / 10; ++y)
      for (int x = f3.width * 75 / 100; x < f3.width; ++x)
        bar_changed += std::memcmp(f3.pixel(x, y), f4.pixel(x, y), 4) != 0;
    EXPECT_EQ(bar_changed, 0) << d;
  }
}

// Without --bins a 3D file's fields are binned as `grainflow run` bins DEM fields: no bin
// narrower than two of the largest diameters. Spheres of radius 1 and 0.5 in a 10 × 8 × 21
// box: 4 wide bins give 2 × 5 on the xz plane (10/4, 21/4), 2 × 2 on xy; --bins rules when
// given; a 2D file keeps 60 × 60. The temperature bar says what the map is: m<C²>/3 with a
// mass column, the velocity variance <C²>/3 without (the file's units, whatever they are).
TEST(CliRender, ThreeDFieldBinsAreTwoDiametersWideAndTheTemperatureSaysWhatItIs) {
  const fs::path dir = fresh_dir("render_bins_in");
  fs::create_directories(dir);
  const std::string head = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff ff\n0 10\n0 8\n0 21\n";
  const fs::path plain = dir / "plain.lammpstrj", massive = dir / "mass.lammpstrj";
  std::ofstream(plain) << head << "ITEM: ATOMS id type x y z vx vy vz radius\n1 1 2 2 2 0 0 1 1\n2 1 6 4 2 1 0 0 0.5\n"
                          "3 1 5 5 9 0 1 0 0.5\n";
  std::ofstream(massive) << head << "ITEM: ATOMS id type x y z vx vy vz radius mass\n1 1 2 2 2 0 0 1 1 8\n"
                            "2 1 6 4 2 1 0 0 0.5 1\n3 1 5 5 9 0 1 0 0.5 1\n";
  const std::string opts = " --size 240 160 --no-mp4 --panels density,temperature -o ";
  const Result xz = run("render " + plain.string() + opts + fresh_dir("render_bins_xz").string());
  ASSERT_EQ(xz.status, 0) << xz.output;
  EXPECT_TRUE(contains(xz.output, "fields on 2 × 5 bins of the xz plane (no finer than two diameters)")) << xz.output;
  EXPECT_TRUE(contains(xz.output, "temperature map: <C²>/3")) << xz.output;
  const Result xy = run("render " + massive.string() + opts + fresh_dir("render_bins_xy").string() + " --plane xy");
  ASSERT_EQ(xy.status, 0) << xy.output;
  EXPECT_TRUE(contains(xy.output, "fields on 2 × 2 bins of the xy plane")) << xy.output;
  EXPECT_TRUE(contains(xy.output, "temperature map: m<C²>/3")) << xy.output;
  const Result given = run("render " + plain.string() + opts + fresh_dir("render_bins_given").string() + " --bins 7 3");
  ASSERT_EQ(given.status, 0) << given.output;
  EXPECT_TRUE(contains(given.output, "fields on 7 × 3 bins of the xz plane;")) << given.output;
  const Result flat = run("render " + data + "/particles/lammps_scaled_2d.lammpstrj --size 160 160 --no-mp4 --panels density -o " +
                          fresh_dir("render_bins_2d").string());
  ASSERT_EQ(flat.status, 0) << flat.output;
  EXPECT_TRUE(contains(flat.output, "fields on 60 × 60 bins of the xy plane;")) << flat.output;
  // The pour starts empty: the grid comes from its first frame with spheres (radii up to
  // 0.5984 → 2.39 wide bins: 2 × 5 on the 6 × 12 xz plane).
  const Result pour_run = run("render " + pour + " --size 160 120 --last 2 --no-mp4 --panels density -o " +
                              fresh_dir("render_bins_pour").string());
  ASSERT_EQ(pour_run.status, 0) << pour_run.output;
  EXPECT_TRUE(contains(pour_run.output, "fields on 2 × 5 bins of the xz plane")) << pour_run.output;
}

// A 2D dump periodic in x with a disk across the edge x = 10: drawn on both sides.
TEST(CliRender, PeriodicImagesOfA2DFile) {
  const fs::path dir = fresh_dir("render_periodic_in");
  fs::create_directories(dir);
  const fs::path file = dir / "edge.lammpstrj";
  std::ofstream(file) << "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n-0.5 0.5\n"
                         "ITEM: ATOMS id type x y z radius\n1 1 9.9 5 0 1.5\n";
  const fs::path on = fresh_dir("render_periodic_on"), off = fresh_dir("render_periodic_off");
  const std::string base = "render " + file.string() + " --size 100 100 --no-mp4 --no-annotations -o ";
  ASSERT_EQ(run(base + on.string()).status, 0);
  ASSERT_EQ(run(base + off.string() + " --no-periodic-images").status, 0);
  const Image a = read_png(on / "frames/frame_000000.png"), b = read_png(off / "frames/frame_000000.png");
  // Near the left edge, at mid height: the image disk is drawn only with periodic images.
  auto dark_left = [](const Image& im) {
    int n = 0;
    for (int x = 6; x < 14; ++x) n += im.pixel(x, 50)[0] < 200;  // inside the outline at x ≈ 3
    return n;
  };
  EXPECT_GT(dark_left(a), 3);
  EXPECT_EQ(dark_left(b), 0);
}

// `grainflow diff DIR_A DIR_B`: golden runs of a user's own scene.
const std::string box_run = "run " + scenes + "/disks_box.toml --set system.box=[20.0,20.0] --set run.until=8.0"
                            " --set render.size=[64,64] --set output.mp4=false -o ";

TEST(CliDiff, TwoRunsOfTheSameSceneAreTheSame) {
  const fs::path a = fresh_dir("diff_same_a"), b = fresh_dir("diff_same_b");
  ASSERT_EQ(run(box_run + a.string()).status, 0);
  ASSERT_EQ(run(box_run + b.string()).status, 0);
  const Result r = run("diff " + a.string() + " " + b.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "frames: 5 compared, 0 differ, 0 only in one folder")) << r.output;
  EXPECT_TRUE(contains(r.output, "in both")) << r.output;                       // state_digest
  EXPECT_TRUE(contains(r.output, "scene.toml: the same")) << r.output;
  EXPECT_TRUE(contains(r.output, "frame_000004.png")) << r.output;              // the per-frame table
  EXPECT_TRUE(contains(r.output, "inf")) << r.output;                           // PSNR of equal frames
}

TEST(CliDiff, OneChangedSetDiffersAndNamesTheFirstDifferingFrame) {
  const fs::path a = fresh_dir("diff_set_a"), b = fresh_dir("diff_set_b"), heat = fresh_dir("diff_set_heat");
  ASSERT_EQ(run(box_run + a.string()).status, 0);
  ASSERT_EQ(run(box_run + b.string() + " --set system.kT=0.03").status, 0);
  const Result r = run("diff " + a.string() + " " + b.string() + " --out " + heat.string());
  EXPECT_EQ(r.status, 1) << r.output;
  // The first frame whose pixels differ, found here independently.
  std::string first;
  for (int k = 0; k < 5 && first.empty(); ++k) {
    const std::string name = "frame_00000" + std::to_string(k) + ".png";
    if (grainflow::render::compare_images(read_png(a / "frames" / name), read_png(b / "frames" / name)).max_channel_diff > 0)
      first = name;
  }
  ASSERT_FALSE(first.empty());
  EXPECT_TRUE(contains(r.output, "first differing frame: " + first)) << r.output;
  EXPECT_TRUE(contains(r.output, "system.kT: 0.02 (A) vs 0.03 (B)")) << r.output;
  EXPECT_TRUE(contains(r.output, "state_digest: DIFFERENT")) << r.output;
  EXPECT_TRUE(fs::exists(heat / "frames" / first));
  // The same tolerances as for two PNGs: loose enough, the frames pass, but the scene
  // and the final state still differ.
  const Result loose = run("diff " + a.string() + " " + b.string() + " --max-channel 255");
  EXPECT_EQ(loose.status, 1) << loose.output;
  EXPECT_TRUE(contains(loose.output, "0 differ")) << loose.output;
  // The heat-map folder is not written over without --force.
  EXPECT_EQ(run("diff " + a.string() + " " + b.string() + " --out " + heat.string()).status, 2);
  EXPECT_EQ(run("diff " + a.string() + " " + b.string() + " --out " + heat.string() + " --force").status, 1);
}

TEST(CliDiff, FramesInOneFolderOnlyAreDifferences) {
  const fs::path a = fresh_dir("diff_len_a"), b = fresh_dir("diff_len_b");
  ASSERT_EQ(run(box_run + a.string()).status, 0);
  ASSERT_EQ(run(box_run + b.string() + " --set run.until=4.0").status, 0);  // frames 0..2
  const Result r = run("diff " + a.string() + " " + b.string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "only in A")) << r.output;
  EXPECT_TRUE(contains(r.output, "first differing frame: frame_000003.png")) << r.output;
  EXPECT_TRUE(contains(r.output, "2 only in one folder")) << r.output;
}

TEST(CliDiff, WhatIsNotTwoRunFoldersIsAnError) {
  const fs::path a = fresh_dir("diff_err_a"), empty = fresh_dir("diff_err_empty");
  ASSERT_EQ(run(box_run + a.string()).status, 0);
  fs::create_directories(empty);
  EXPECT_EQ(run("diff " + a.string() + " " + empty.string()).status, 2);
  EXPECT_EQ(run("diff " + a.string() + " " + (a / "frames/frame_000000.png").string()).status, 2);
  const Result missing = run("diff " + a.string() + " " + (a / "nothing").string());
  EXPECT_EQ(missing.status, 2) << missing.output;
}

}  // namespace
