// `grainflow render FILE -o DIR`: renders particle snapshots written by other tools
// (LAMMPS/LIGGGHTS text dumps, extended XYZ) headlessly → DIR/frames/*.png and DIR/<name>.mp4.
// Encoding runs on its own thread (AsyncSink) while the next frame is read and drawn.
// With --panels, each frame's particles are binned (engine/core/binning.hpp; 3D files
// averaged over z onto the x–y plane) and the fields drawn in a grid of panels.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/core/binning.hpp"
#include "engine/core/error.hpp"
#include "engine/io/particle_reader.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "render/output/fan_out_sink.hpp"
#include "render/output/mp4_sink.hpp"
#include "render/output/mp4_writer.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "render/panel_layout.hpp"
#include "scenes/src/cli/commands.hpp"
#include "scenes/src/engines/field_snapshot.hpp"
#include "scenes/src/engines/particle_snapshot.hpp"
#include "scenes/src/run/interrupt.hpp"
#include "scenes/src/run/run_folder.hpp"

namespace grainflow::scenes {
namespace fs = std::filesystem;
namespace {

struct RenderArgs {
  std::string input;
  std::string out_dir;
  std::string backend = "auto";
  std::vector<int> size{1280, 720};
  std::string colour_by;  // empty: default_colour_attribute()
  std::string colormap = "viridis";
  std::vector<double> range;
  int msaa = -1;  // -1: 4 for 3D, 0 for 2D (disks anti-alias themselves)
  int fps = 30;
  int crf = 20;
  std::string preset = "veryfast";
  bool png = true;
  bool mp4 = true;
  int every = 1;
  double azimuth = 35, elevation = 25;
  bool orthographic = false;
  bool force = false;
  std::vector<std::string> panels;  // empty: one full-frame particle picture
  std::vector<int> bins{60, 60};
  std::vector<int> layout;          // cols rows; default: a near-square grid for the panels
};

// Bins the frame on the x–y plane of its box and stores the fields in the snapshot.
void add_binned_fields(const core::ParticleFrame& frame, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                       const std::vector<int>& bins, render::Snapshot& s) {
  core::BinningOptions opt;
  opt.grid.nx = bins[0];
  opt.grid.ny = bins[1];
  opt.grid.lo = Vec2(lo.x(), lo.y());
  opt.grid.hi = Vec2(hi.x(), hi.y());
  set_binned_fields(core::bin_frame(frame, opt), s);
  s.labels.clear();
  char buf[64];
  if (std::isfinite(frame.time)) {
    std::snprintf(buf, sizeof buf, "%g", frame.time);
    s.labels.emplace_back("t", buf);
  } else if (frame.timestep >= 0) {
    s.labels.emplace_back("step", std::to_string(frame.timestep));
  }
  s.labels.emplace_back("N", std::to_string(frame.size()));
  s.labels.emplace_back("bins", std::to_string(bins[0]) + " × " + std::to_string(bins[1]));
}

int run_render(const RenderArgs& a) {
  if (a.size.size() != 2 || a.size[0] < 16 || a.size[1] < 16 || a.size[0] > 8192 || a.size[1] > 8192)
    throw Error("--size must be two integers W H, each in 16..8192");
  if (!a.range.empty() && (a.range.size() != 2 || !(a.range[0] < a.range[1]) || !std::isfinite(a.range[0]) ||
                          !std::isfinite(a.range[1])))
    throw Error("--range must be two finite numbers LO HI with LO < HI");
  // A NaN angle gives a blank frame and exit 0: refuse it.
  if (!std::isfinite(a.azimuth) || !std::isfinite(a.elevation))
    throw Error("--azimuth and --elevation must be finite numbers of degrees");
  if (a.every < 1) throw Error("--every must be ≥ 1");
  if (!a.png && !a.mp4) throw Error("nothing to write: --no-png and --no-mp4 together");
  if (a.bins.size() != 2 || a.bins[0] < 1 || a.bins[1] < 1 || a.bins[0] > 4096 || a.bins[1] > 4096)
    throw Error("--bins must be two integers NX NY, each in 1..4096");
  std::optional<render::FrameLayout> layout;
  if (!a.panels.empty()) {
    int cols = 0, rows = 0;
    if (!a.layout.empty()) {
      if (a.layout.size() != 2) throw Error("--layout must be two integers COLS ROWS");
      cols = a.layout[0];
      rows = a.layout[1];
    } else {
      cols = int(std::ceil(std::sqrt(double(a.panels.size()))));
      rows = int((a.panels.size() + std::size_t(cols) - 1) / std::size_t(cols));
    }
    layout = render::make_layout(cols, rows, a.panels);  // names and fit checked here
  } else if (!a.layout.empty()) {
    throw Error("--layout needs --panels (e.g. --panels particles,density,temperature,streamlines)");
  }

  auto reader = io::open_particle_file(a.input);
  core::ParticleFrame frame;
  if (!reader->next(frame)) throw Error("'" + a.input + "' holds no frame");

  // Option values, the colour attribute and the GL context are checked before anything is
  // created on disk.
  const render::Colormap colormap = render::Colormap::by_name(a.colormap);
  const render::Backend backend = render::parse_backend(a.backend);
  const std::string attribute = a.colour_by.empty() ? default_colour_attribute(frame) : a.colour_by;
  render::Snapshot snapshot;
  to_snapshot(frame, attribute, snapshot);  // throws naming the file's columns
  const std::string stem = fs::path(a.input).stem().string();
  render::Mp4Options opt;
  opt.fps = a.fps;
  opt.crf = a.crf;
  opt.preset = a.preset;
  if (a.mp4) render::check_mp4_options(stem + ".mp4", opt);
  std::string notice;
  auto ctx = render::create_context(backend, &notice);
  if (!notice.empty()) std::fprintf(stderr, "grainflow: %s\n", notice.c_str());
  const int msaa = a.msaa >= 0 ? a.msaa : (frame.dim == 3 ? 4 : 0);
  render::FrameRenderer renderer(*ctx, a.size[0], a.size[1], msaa);

  // The same folder rules as `grainflow run`: a folder holding earlier output is not
  // overwritten without --force (which removes only what grainflow wrote there), and an
  // unwritable one fails before the first frame.
  RunFolder folder = RunFolder::open(a.out_dir, a.force ? RunFolderMode::Force : RunFolderMode::Fresh);
  const fs::path dir = folder.dir();
  const fs::path mp4_path = dir / (stem + ".mp4");
  std::unique_ptr<render::FrameSink> output;
  try {
    std::vector<std::unique_ptr<render::FrameSink>> sinks;
    if (a.png) {
      folder.claim(kFrameFiles);
      sinks.push_back(std::make_unique<render::PngSequenceSink>(dir / "frames"));
    }
    if (a.mp4) {
      folder.claim(stem + ".mp4");
      sinks.push_back(std::make_unique<render::Mp4Sink>(mp4_path, opt));
    }
    output = render::parallel_sinks(std::move(sinks));
  } catch (...) {
    folder.abandon();  // a failed start leaves the folder as it was
    throw;
  }

  render::FrameStyle style;
  style.colormap = colormap;
  style.camera.azimuth_deg = a.azimuth;
  style.camera.elevation_deg = a.elevation;
  style.camera.orthographic = a.orthographic;
  // The camera and the colour range stay fixed for the whole video, taken from the first
  // frame (or --range), so frames can be compared with one another.
  Eigen::Vector3d lo, hi;
  frame_bounds(frame, lo, hi);
  to_snapshot(frame, attribute, snapshot);
  if (!a.range.empty()) style.range = std::pair{a.range[0], a.range[1]};
  else if (!snapshot.attribute_categorical && !attribute.empty()) style.range = render::finite_range(snapshot.attribute);

  std::fprintf(stderr, "grainflow: %s (%s, %s) → %s  [%s, %dx%d, colour by %s]\n", a.input.c_str(),
               std::string(reader->format()).c_str(), frame.dim == 3 ? "3D spheres" : "2D disks", dir.c_str(),
               ctx->backend().c_str(), a.size[0], a.size[1], attribute.empty() ? "(none)" : attribute.c_str());
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_report = start;
  std::int64_t read = 0, written = 0;
  // Ctrl-C / SIGTERM as in `grainflow run`: stop after the frame at hand, finish the MP4
  // and keep the frames written so far.
  InterruptGuard interrupts;
  bool interrupted = false;
  do {
    if (stop_requested()) {
      interrupted = true;
      break;
    }
    if (read++ % a.every != 0) continue;
    to_snapshot(frame, attribute, snapshot);
    snapshot.lo = lo;
    snapshot.hi = hi;
    if (layout) add_binned_fields(frame, lo, hi, a.bins, snapshot);
    output->consume(layout ? renderer.render(snapshot, style, *layout) : renderer.render(snapshot, style), written,
                   snapshot.time);
    ++written;
    const auto now = clock::now();
    if (now - last_report > std::chrono::seconds(2)) {
      const double s = std::chrono::duration<double>(now - start).count();
      std::fprintf(stderr, "grainflow: %lld frames, %.1f frames/s\n", static_cast<long long>(written), written / s);
      last_report = now;
    }
  } while (reader->next(frame));
  output->finish();
  const double seconds = std::chrono::duration<double>(clock::now() - start).count();
  std::printf("%lld frames in %.2f s (%.1f frames/s)\n", static_cast<long long>(written), seconds,
              written / seconds);
  if (a.png) std::printf("  frames: %s\n", (dir / "frames").c_str());
  if (a.mp4) std::printf("  video:  %s\n", mp4_path.c_str());
  if (interrupted) std::printf("interrupted after %lld frames\n", static_cast<long long>(written));
  return interrupted ? 130 : 0;
}

}  // namespace

namespace {
// "a|b|c" of a name table, for help texts that list what the table allows.
std::string joined(std::span<const std::string_view> names, std::string_view sep) {
  std::string s;
  for (auto n : names) s += (s.empty() ? "" : std::string(sep)) + std::string(n);
  return s;
}
}  // namespace

void setup_render_command(CLI::App& app, int& status) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Render particle files (LAMMPS/LIGGGHTS dumps, extended XYZ) to PNG + MP4");
  cmd->add_option("file", args->input, "Particle file: LAMMPS/LIGGGHTS text dump or (extended) XYZ")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->out_dir, "Output folder (frames/ and <file>.mp4 go here)")->required();
  cmd->add_option("--backend", args->backend, "Off-screen GL backend: auto|egl|osmesa")->capture_default_str();
  cmd->add_option("--size", args->size, "Frame size in pixels: W H")->expected(2)->capture_default_str();
  cmd->add_option("--color-by", args->colour_by,
                  "Per-particle column to colour by (speed, type, radius, z, vx, … any file column); "
                  "default: speed if velocities, else type");
  cmd->add_option("--colormap", args->colormap, "Colour map: " + joined(render::Colormap::names(), "|"))
      ->capture_default_str();
  cmd->add_option("--range", args->range, "Colour range LO HI (default: the first frame's range)")->expected(2);
  cmd->add_option("--msaa", args->msaa, "Multisample count (default 4 for 3D, 0 for 2D)");
  cmd->add_option("--fps", args->fps, "Video frame rate")->capture_default_str();
  cmd->add_option("--crf", args->crf, "H.264 quality, 0 (lossless) .. 51")->capture_default_str();
  cmd->add_option("--preset", args->preset, "x264 preset (ultrafast … veryslow)")->capture_default_str();
  cmd->add_option("--every", args->every, "Render every N-th frame")->capture_default_str();
  cmd->add_option("--azimuth", args->azimuth, "3D camera azimuth, degrees")->capture_default_str();
  cmd->add_option("--elevation", args->elevation, "3D camera elevation, degrees")->capture_default_str();
  cmd->add_flag("--orthographic", args->orthographic, "3D: orthographic instead of perspective camera");
  cmd->add_flag("!--no-png", args->png, "Do not write the PNG sequence");
  cmd->add_flag("!--no-mp4", args->mp4, "Do not write the MP4");
  cmd->add_flag("--force", args->force, "Replace frames already in the output folder");
  cmd->add_option("--panels", args->panels,
                  "Panels of each frame, filled row by row: " + joined(render::panel_names(), ", ") +
                      " (fields binned from the particles; 3D: averaged over z)")
      ->delimiter(',');
  cmd->add_option("--bins", args->bins, "Bins of the field grid: NX NY")->expected(2)->capture_default_str();
  cmd->add_option("--layout", args->layout, "Panel grid: COLS ROWS (default: near-square for the panels)")
      ->expected(2);
  cmd->callback([args, &status] { status = run_render(*args); });
}

}  // namespace grainflow::scenes
