// `grainflow diff A.png B.png`: compares two images with the project's comparator
// (render/image/compare.hpp) — the same metrics and tolerances the golden-image tests use.
// `grainflow diff DIR_A DIR_B`: compares two run (or render) folders — every frame of
// frames/ with the same tolerances, the state_digest of run.json and the effective
// scene.toml key by key — for users who keep golden runs of their own scenes.
// Exit status: 0 within tolerance, 1 different, 2 error (missing file, not a PNG, sizes differ).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <iomanip>
#include <sstream>
#include <tuple>
#include <string>

#include <toml++/toml.h>

#include "engine/core/error.hpp"
#include "render/image/compare.hpp"
#include "render/output/png_io.hpp"
#include "scenes/src/cli/commands.hpp"
#include "scenes/src/outputs/run_output.hpp"
#include "scenes/src/run/run_folder.hpp"

namespace grainflow::scenes {

namespace {

namespace fs = std::filesystem;

struct DiffArgs {
  std::string a, b, out;
  render::CompareOptions options;
  bool force = false;
};

// PSNR for the table: "inf" for equal images.
std::string psnr_text(double db) { return std::isinf(db) ? "inf" : (std::ostringstream() << std::fixed << std::setprecision(2) << db).str(); }

int diff_images(const DiffArgs& args) {
  // Sizes from the headers first: two images of different sizes are not decoded at all,
  // and an image too large to compare is refused before its pixels are reserved.
  const auto sa = render::png_size(args.a), sb = render::png_size(args.b);
  if (sa != sb)
    throw Error("image comparison: sizes differ (" + std::to_string(sa.first) + "x" + std::to_string(sa.second) +
                " vs " + std::to_string(sb.first) + "x" + std::to_string(sb.second) + ": " + args.a + ", " + args.b +
                ")");
  constexpr double kMaxPixels = 16384.0 * 16384.0;  // 1 GiB of RGBA per image
  if (double(sa.first) * sa.second > kMaxPixels)
    throw Error("the images are " + std::to_string(sa.first) + "x" + std::to_string(sa.second) +
                "; allowed: at most 16384 × 16384 pixels");
  const render::Image a = render::read_png(args.a);
  const render::Image b = render::read_png(args.b);
  const render::CompareResult r = render::compare_images(a, b, args.options);
  std::printf("size: %dx%d (%lld pixels)\n", a.width, a.height, static_cast<long long>(r.pixel_count));
  std::printf("max channel difference: %d\n", r.max_channel_diff);
  std::printf("mean absolute difference: %.6f (per channel, 0..255)\n", r.mean_abs_diff);
  std::printf("pixels over tolerance (max channel difference > %d): %lld (fraction %.6g, allowed %.6g)\n",
              args.options.max_channel, static_cast<long long>(r.pixels_over), r.fraction_over,
              args.options.max_fraction);
  std::printf("PSNR: %s dB, SSIM: %.6f\n", psnr_text(r.psnr_db).c_str(), r.max_channel_diff == 0 ? 1.0 : render::ssim(a, b));
  if (!args.out.empty()) {
    render::write_png(args.out, render::diff_heatmap(a, b));
    std::printf("difference image: %s\n", args.out.c_str());
  }
  std::printf("result: %s\n", r.passed ? "within tolerance" : "DIFFERENT");
  return r.passed ? 0 : 1;
}

// The frames/frame_*.png names of a run folder, sorted.
std::set<std::string> frame_names(const fs::path& dir) {
  std::set<std::string> names;
  std::error_code ec;
  if (!fs::is_directory(dir / "frames", ec)) return names;
  for (const auto& e : fs::directory_iterator(dir / "frames")) {
    const std::string n = e.path().filename().string();
    if (e.is_regular_file() && n.rfind("frame_", 0) == 0 && e.path().extension() == ".png") names.insert(n);
  }
  return names;
}

std::optional<std::string> read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The string value of "key": "…" in run.json (written by grainflow: one key per line).
std::optional<std::string> json_string(const std::string& json, const std::string& key) {
  const std::string pat = "\"" + key + "\": \"";
  const auto i = json.find(pat);
  if (i == std::string::npos) return std::nullopt;
  const auto j = json.find('"', i + pat.size());
  if (j == std::string::npos) return std::nullopt;
  return json.substr(i + pat.size(), j - i - pat.size());
}

// A TOML value as the scene file would write it; floats in their shortest exact form
// (0.03, not toml++'s 0.029999999999999999).
std::string value_text(const toml::node& v) {
  if (const auto* d = v.as_floating_point()) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, d->get());
    return std::string(buf, r.ptr);
  }
  if (const auto* arr = v.as_array()) {
    std::string s = "[";
    for (const auto& e : *arr) s += (s.size() > 1 ? ", " : "") + value_text(e);
    return s + "]";
  }
  std::ostringstream s;
  v.visit([&](const auto& node) { s << node; });
  return s.str();
}

// Every key of an effective scene as "section.key" → its TOML value (comments ignored).
void flatten(const toml::table& t, const std::string& prefix, std::map<std::string, std::string>& out) {
  for (const auto& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = v.as_table()) {
      flatten(*sub, path, out);
    } else {
      out[path] = value_text(v);
    }
  }
}

std::map<std::string, std::string> scene_keys(const fs::path& file) {
  try {
    std::map<std::string, std::string> keys;
    flatten(toml::parse_file(file.string()), "", keys);
    return keys;
  } catch (const toml::parse_error& e) {
    throw Error(file.string() + ": not a readable scene file: " + std::string(e.description()));
  }
}

int diff_folders(const DiffArgs& args) {
  const fs::path a = args.a, b = args.b;
  const auto fa = frame_names(a), fb = frame_names(b);
  const bool ja = fs::exists(a / "run.json"), jb = fs::exists(b / "run.json");
  const bool sa = fs::exists(a / "scene.toml"), sb = fs::exists(b / "scene.toml");
  for (const auto& [dir, frames, json, scene] : {std::tuple{a, fa.size(), ja, sa}, std::tuple{b, fb.size(), jb, sb}})
    if (frames == 0 && !json && !scene)
      throw Error("'" + dir.string() + "' is not a run folder: it holds no frames/frame_*.png, run.json or scene.toml");

  // Heat maps of the frames that differ go to --out DIR/frames/, named as the frames; DIR
  // follows the run folders' rules (not over earlier output without --force).
  std::optional<RunFolder> out;
  if (!args.out.empty()) {
    out.emplace(RunFolder::open(args.out, args.force ? RunFolderMode::Force : RunFolderMode::Fresh));
    out->claim(kFrameFiles);
  }

  std::printf("comparing run folders\n  A: %s\n  B: %s\n", a.c_str(), b.c_str());
  std::printf("a frame differs when more than a fraction %.6g of its pixels differ by more than %d in a channel\n\n",
              args.options.max_fraction, args.options.max_channel);
  std::set<std::string> all = fa;
  all.insert(fb.begin(), fb.end());
  std::printf("%-22s %5s %10s %9s %9s %10s  %s\n", "frame", "max", "mean", "PSNR dB", "SSIM", "over", "result");
  std::optional<std::string> first_bad;
  std::size_t compared = 0, differing = 0, only_one = 0, heat_maps = 0;
  for (const auto& name : all) {
    const bool in_a = fa.count(name) > 0, in_b = fb.count(name) > 0;
    if (!in_a || !in_b) {
      ++only_one;
      if (!first_bad) first_bad = name;
      std::printf("%-22s %5s %10s %9s %9s %10s  only in %s\n", name.c_str(), "-", "-", "-", "-", "-", in_a ? "A" : "B");
      continue;
    }
    const fs::path pa = a / "frames" / name, pb = b / "frames" / name;
    const auto za = render::png_size(pa), zb = render::png_size(pb);
    ++compared;
    if (za != zb) {
      ++differing;
      if (!first_bad) first_bad = name;
      std::printf("%-22s %5s %10s %9s %9s %10s  DIFFERENT (sizes %dx%d vs %dx%d)\n", name.c_str(), "-", "-", "-", "-",
                  "-", za.first, za.second, zb.first, zb.second);
      continue;
    }
    const render::Image ia = render::read_png(pa), ib = render::read_png(pb);
    const render::CompareResult r = render::compare_images(ia, ib, args.options);
    const double similarity = r.max_channel_diff == 0 ? 1.0 : render::ssim(ia, ib);
    std::printf("%-22s %5d %10.6f %9s %9.6f %10.6g  %s\n", name.c_str(), r.max_channel_diff, r.mean_abs_diff,
                psnr_text(r.psnr_db).c_str(), similarity, r.fraction_over,
                r.passed ? (r.max_channel_diff == 0 ? "same" : "within tolerance") : "DIFFERENT");
    if (!r.passed) {
      ++differing;
      if (!first_bad) first_bad = name;
      if (out) {
        render::write_png(out->frames_dir() / name, render::diff_heatmap(ia, ib));
        ++heat_maps;
      }
    }
  }
  bool same = differing == 0 && only_one == 0;
  std::printf("\nframes: %zu compared, %zu differ, %zu only in one folder\n", compared, differing, only_one);
  if (first_bad) std::printf("first differing frame: %s\n", first_bad->c_str());

  // state_digest: a hash of the exact final state, equal for bit-identical runs.
  if (ja || jb) {
    const auto da = ja ? json_string(read_text(a / "run.json").value_or(""), "state_digest") : std::nullopt;
    const auto db = jb ? json_string(read_text(b / "run.json").value_or(""), "state_digest") : std::nullopt;
    if (da && db && *da == *db) {
      std::printf("state_digest: %s in both\n", da->c_str());
    } else {
      same = false;
      std::printf("state_digest: DIFFERENT (A: %s, B: %s)\n", da ? da->c_str() : "none", db ? db->c_str() : "none");
    }
  }
  if (sa || sb) {
    if (!sa || !sb) {
      same = false;
      std::printf("scene.toml: only in %s\n", sa ? "A" : "B");
    } else {
      const auto ka = scene_keys(a / "scene.toml"), kb = scene_keys(b / "scene.toml");
      std::vector<std::string> lines;
      for (const auto& [k, v] : ka) {
        const auto it = kb.find(k);
        if (it == kb.end()) lines.push_back("  " + k + " = " + v + " (A only)");
        else if (it->second != v) lines.push_back("  " + k + ": " + v + " (A) vs " + it->second + " (B)");
      }
      for (const auto& [k, v] : kb)
        if (!ka.count(k)) lines.push_back("  " + k + " = " + v + " (B only)");
      if (lines.empty()) {
        std::printf("scene.toml: the same %zu keys and values\n", ka.size());
      } else {
        same = false;
        std::printf("scene.toml: %zu key%s DIFFER\n", lines.size(), lines.size() == 1 ? "" : "s");
        for (const auto& l : lines) std::printf("%s\n", l.c_str());
      }
    }
  }
  if (out) {
    if (heat_maps == 0) out->abandon();  // nothing written: leave no empty folder behind
    else std::printf("heat maps of the %zu differing frames: %s\n", heat_maps, out->frames_dir().c_str());
  }
  std::printf("result: %s\n", same ? "the same within tolerance" : "DIFFERENT");
  return same ? 0 : 1;
}

int run_diff(const DiffArgs& args) {
  std::error_code ec;
  const bool da = fs::is_directory(args.a, ec), db = fs::is_directory(args.b, ec);
  if (da && db) return diff_folders(args);
  if (da || db)
    throw Error("diff compares two PNG images or two run folders; '" + (da ? args.a : args.b) + "' is a folder but '" +
                (da ? args.b : args.a) + "' is not");
  if (args.force) throw Error("--force is for --out folders of run-folder comparisons");
  return diff_images(args);
}

}  // namespace

void setup_diff_command(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand(
      "diff", "Compare two PNG images, or two run folders frame by frame (exit 0 within tolerance, 1 different, 2 error)");
  auto args = std::make_shared<DiffArgs>();
  cmd->add_option("A", args->a, "First PNG image, or run folder")->required();
  cmd->add_option("B", args->b, "Second PNG image, or run folder")->required();
  cmd->add_option("--max-channel", args->options.max_channel,
                  "Per-pixel tolerance: a pixel counts as different when its largest channel difference "
                  "(R, G, B, A) exceeds N")
      ->check(CLI::Range(0, 255))
      ->capture_default_str();
  cmd->add_option("--max-fraction", args->options.max_fraction,
                  "Allowed fraction of pixels over the per-pixel tolerance")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--out", args->out,
                  "Write a heat map of the differences (black = equal) to this PNG; for two run folders, a folder "
                  "that gets DIR/frames/frame_NNNNNN.png for each differing frame");
  cmd->add_flag("--force", args->force, "Run folders: replace the heat maps an earlier diff wrote in --out");
  cmd->callback([args, &status] { status = run_diff(*args); });
}

}  // namespace grainflow::scenes
