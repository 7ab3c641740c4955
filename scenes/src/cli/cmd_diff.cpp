// `grainflow diff A.png B.png`: compares two images with the project's comparator
// (render/image/compare.hpp) — the same metrics and tolerances the golden-image tests use.
// Exit status: 0 within tolerance, 1 different, 2 error (missing file, not a PNG, sizes differ).
#include <cstdio>
#include <memory>
#include <string>

#include "engine/core/error.hpp"
#include "render/image/compare.hpp"
#include "render/output/png_io.hpp"
#include "scenes/src/cli/commands.hpp"

namespace grainflow::scenes {

namespace {

struct DiffArgs {
  std::string a, b, out;
  render::CompareOptions options;
};

int run_diff(const DiffArgs& args) {
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
  if (!args.out.empty()) {
    render::write_png(args.out, render::diff_heatmap(a, b));
    std::printf("difference image: %s\n", args.out.c_str());
  }
  std::printf("result: %s\n", r.passed ? "within tolerance" : "DIFFERENT");
  return r.passed ? 0 : 1;
}

}  // namespace

void setup_diff_command(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("diff", "Compare two PNG images (exit 0 within tolerance, 1 different, 2 error)");
  auto args = std::make_shared<DiffArgs>();
  cmd->add_option("A", args->a, "First PNG image")->required();
  cmd->add_option("B", args->b, "Second PNG image")->required();
  cmd->add_option("--max-channel", args->options.max_channel,
                  "Per-pixel tolerance: a pixel counts as different when its largest channel difference "
                  "(R, G, B, A) exceeds N")
      ->check(CLI::Range(0, 255))
      ->capture_default_str();
  cmd->add_option("--max-fraction", args->options.max_fraction,
                  "Allowed fraction of pixels over the per-pixel tolerance")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Write a heat map of the differences (black = equal) to this PNG");
  cmd->callback([args, &status] { status = run_diff(*args); });
}

}  // namespace grainflow::scenes
