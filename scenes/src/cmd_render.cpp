// `grainflow render FILE -o DIR`: renders particle snapshots written by other tools
// (LAMMPS/LIGGGHTS text dumps, extended XYZ) headlessly → DIR/frames/*.png and DIR/<name>.mp4.
// Encoding runs on its own thread (AsyncSink) while the next frame is read and drawn.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/particle_reader.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "render/output/async_sink.hpp"
#include "render/output/mp4_sink.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "scenes/src/commands.hpp"
#include "scenes/src/particle_snapshot.hpp"

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
};

// A folder that already holds output is never overwritten silently.
void prepare_output_dir(const fs::path& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw Error("output '" + dir.string() + "' exists and is not a directory");
  if (fs::exists(dir / "frames", ec) && !fs::is_empty(dir / "frames", ec) && !force)
    throw Error("output folder '" + dir.string() + "' already holds frames; choose another -o or pass --force");
  fs::create_directories(dir, ec);
  if (ec) throw Error("cannot create output folder '" + dir.string() + "': " + ec.message());
  // Probe writability now rather than after the first (possibly slow) frame.
  const fs::path probe = dir / ".grainflow-write-test";
  if (std::FILE* f = std::fopen(probe.c_str(), "w")) {
    std::fclose(f);
    fs::remove(probe, ec);
  } else {
    throw Error("output folder '" + dir.string() + "' is not writable");
  }
  if (force) fs::remove_all(dir / "frames", ec);
}

int run_render(const RenderArgs& a) {
  if (a.size.size() != 2 || a.size[0] < 16 || a.size[1] < 16 || a.size[0] > 8192 || a.size[1] > 8192)
    throw Error("--size must be two integers W H, each in 16..8192");
  if (!a.range.empty() && (a.range.size() != 2 || !(a.range[0] < a.range[1])))
    throw Error("--range must be two numbers LO HI with LO < HI");
  if (a.every < 1) throw Error("--every must be ≥ 1");
  if (!a.png && !a.mp4) throw Error("nothing to write: --no-png and --no-mp4 together");

  auto reader = core::open_particle_file(a.input);
  core::ParticleFrame frame;
  if (!reader->next(frame)) throw Error("'" + a.input + "' holds no frame");

  const fs::path dir(a.out_dir);
  prepare_output_dir(dir, a.force);
  const render::Colormap colormap = render::Colormap::by_name(a.colormap);
  const std::string attribute = a.colour_by.empty() ? default_colour_attribute(frame) : a.colour_by;

  std::string notice;
  auto ctx = render::create_context(render::parse_backend(a.backend), &notice);
  if (!notice.empty()) std::fprintf(stderr, "grainflow: %s\n", notice.c_str());
  const int msaa = a.msaa >= 0 ? a.msaa : (frame.dim == 3 ? 4 : 0);
  render::FrameRenderer renderer(*ctx, a.size[0], a.size[1], msaa);

  std::vector<std::unique_ptr<render::FrameSink>> sinks;
  if (a.png) sinks.push_back(std::make_unique<render::PngSequenceSink>(dir / "frames"));
  const fs::path mp4_path = dir / (fs::path(a.input).stem().string() + ".mp4");
  if (a.mp4) {
    render::Mp4Options opt;
    opt.fps = a.fps;
    opt.crf = a.crf;
    opt.preset = a.preset;
    sinks.push_back(std::make_unique<render::Mp4Sink>(mp4_path, opt));
  }
  render::AsyncSink output(std::move(sinks));

  render::FrameStyle style;
  style.colormap = colormap;
  style.camera.azimuth_deg = a.azimuth;
  style.camera.elevation_deg = a.elevation;
  style.camera.orthographic = a.orthographic;
  render::Snapshot snapshot;
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
  do {
    if (read++ % a.every != 0) continue;
    to_snapshot(frame, attribute, snapshot);
    snapshot.lo = lo;
    snapshot.hi = hi;
    output.consume(renderer.render(snapshot, style), written, snapshot.time);
    ++written;
    const auto now = clock::now();
    if (now - last_report > std::chrono::seconds(2)) {
      const double s = std::chrono::duration<double>(now - start).count();
      std::fprintf(stderr, "grainflow: %lld frames, %.1f frames/s\n", static_cast<long long>(written), written / s);
      last_report = now;
    }
  } while (reader->next(frame));
  output.finish();
  const double seconds = std::chrono::duration<double>(clock::now() - start).count();
  std::printf("%lld frames in %.2f s (%.1f frames/s)\n", static_cast<long long>(written), seconds,
              written / seconds);
  if (a.png) std::printf("  frames: %s\n", (dir / "frames").c_str());
  if (a.mp4) std::printf("  video:  %s\n", mp4_path.c_str());
  return 0;
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
  cmd->add_option("--colormap", args->colormap, "viridis|inferno|magma|turbo|cool-warm|tab10")->capture_default_str();
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
  cmd->callback([args, &status] { status = run_render(*args); });
}

}  // namespace grainflow::scenes
