// `grainflow render FILE -o DIR`: renders particle snapshots written by other tools
// (LAMMPS/LIGGGHTS text dumps, extended XYZ) headlessly → DIR/frames/*.png and DIR/<name>.mp4.
// Encoding runs on its own thread (AsyncSink) while the next frame is read and drawn.
// With --panels, each frame's particles are binned (engine/core/binning.hpp; 3D files on a
// chosen plane, averaged across a slab) and the fields drawn in a grid of panels; without,
// one particle picture with its colour bar (or a legend of categories) and time caption.
// A file still being written (its last frame cut short) gives its complete frames.
#include <algorithm>
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
#include "engine/io/line_reader.hpp"
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
  std::string colormap;   // empty: tab10 for categories (type, id) on particles alone, else viridis
  std::vector<double> range;
  int msaa = -1;  // -1: 4 for 3D, 0 for 2D (disks anti-alias themselves)
  int fps = 30;
  int crf = 20;
  std::string preset = "veryfast";
  bool png = true;
  bool mp4 = true;
  int every = 1;
  std::int64_t first = 0, last = -1;  // source frame indices, inclusive; last -1: to the end
  double dt = 0;                      // > 0: time = TIMESTEP × dt
  double azimuth = 35, elevation = 25;
  bool orthographic = false;
  double zoom = 1, distance = 0;      // distance 0: the box fits
  std::vector<double> target;
  bool periodic_images = true;
  bool annotations = true;
  bool force = false;
  std::vector<std::string> panels;  // empty: one particle picture (with colour bar or legend and caption)
  std::vector<int> bins;             // empty: 60 × 60 for 2D files; 3D: no finer than two diameters
  std::vector<int> layout;          // cols rows; default: a near-square grid for the panels
  std::string plane;                // empty: xy for 2D files, xz (vertical, under gravity) for 3D
  std::vector<double> slab;         // lo hi across the plane (3D); empty: the whole box
  std::string range_mode = "run";
  std::vector<std::string> map_ranges;  // "panel=lo,hi"
};

// The field plane of --plane.
core::BinPlane field_plane(const std::string& name) {
  try {
    return core::bin_plane(name);
  } catch (const Error&) {
    throw Error("--plane " + name + " is not a plane; allowed: xy, xz, yz");
  }
}

// The field grid when --bins is not given. 3D: as `grainflow run` bins DEM fields, no bin
// narrower than two of the frame's largest diameters (a sphere is binned by its centre:
// finer bins stripe the density with the layers and leave bins without the two samples a
// temperature needs). 2D files keep 60 × 60.
std::array<int, 2> default_bins(const core::ParticleFrame& frame, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                core::BinPlane plane) {
  if (frame.dim == 2) return {60, 60};
  double rmax = 0;
  for (double r : frame.radius) rmax = std::max(rmax, r);
  const auto [u, v] = core::plane_axes(plane);
  return core::bins_no_finer_than(Vec2(hi[u] - lo[u], hi[v] - lo[v]), 4.0 * rmax);
}

// The units of a file's fields are the file's own, unknown here: the bars name only what
// the temperature map is. core::BinAccumulator::temperature is Σ m|C|² / (i N), i = dim,
// with m from a "mass" column, else 1: then it is a velocity variance, not an energy.
FieldUnits file_field_units(const core::ParticleFrame& frame) {
  FieldUnits u;
  u.temperature_label = std::string(frame.column("mass") ? "m<C²>/" : "<C²>/") + (frame.dim == 2 ? "2" : "3");
  return u;
}

// Bins the frame on the chosen plane of its box (3D: within the slab) and stores the
// fields in the snapshot.
void add_binned_fields(const core::ParticleFrame& frame, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                       const std::array<int, 2>& bins, core::BinPlane plane, const std::vector<double>& slab,
                       render::Snapshot& s) {
  std::optional<std::array<double, 2>> across;
  if (!slab.empty()) across = std::array{slab[0], slab[1]};
  set_binned_fields(core::bin_frame(frame, core::plane_binning(plane, lo, hi, bins, across)), s, file_field_units(frame));
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The frame's time: the file's own (LAMMPS `ITEM: TIME`, XYZ Time=), else TIMESTEP × --dt;
// NaN when neither is known.
double frame_time(const core::ParticleFrame& frame, double dt) {
  if (std::isfinite(frame.time)) return frame.time;
  if (dt > 0 && frame.timestep >= 0) return double(frame.timestep) * dt;
  return std::nan("");
}

// The caption: time, step, source frame index, particle count (and bins with fields).
void set_labels(const core::ParticleFrame& frame, std::int64_t index, double time, const std::array<int, 2>* bins,
                render::Snapshot& s) {
  s.labels.clear();
  if (std::isfinite(time)) s.labels.emplace_back("t", number(time));
  if (frame.timestep >= 0) s.labels.emplace_back("step", std::to_string(frame.timestep));
  s.labels.emplace_back("frame", std::to_string(index));
  s.labels.emplace_back("N", std::to_string(frame.size()));
  if (bins) s.labels.emplace_back("bins", std::to_string((*bins)[0]) + " × " + std::to_string((*bins)[1]));
}

// Reads the next frame; false at the end. A file that ends inside a frame (a dump still
// being written) also ends the frames, with a warning naming what was left out.
bool next_frame(io::ParticleReader& reader, core::ParticleFrame& frame, std::int64_t complete) {
  try {
    return reader.next(frame);
  } catch (const io::TruncatedFrame& e) {
    if (complete == 0) throw;
    std::fprintf(stderr,
                 "grainflow: warning: %s\ngrainflow: warning: the file ends inside frame %lld (still being "
                 "written?): it is left out; the %lld complete frames before it are rendered\n",
                 e.what(), static_cast<long long>(complete), static_cast<long long>(complete));
    return false;
  }
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
  if (!(std::isfinite(a.zoom) && a.zoom > 0)) throw Error("--zoom must be a finite number > 0");
  if (!(std::isfinite(a.distance) && a.distance >= 0)) throw Error("--distance must be a finite number > 0");
  if (!a.target.empty() && (a.target.size() != 3 || !std::isfinite(a.target[0]) || !std::isfinite(a.target[1]) ||
                            !std::isfinite(a.target[2])))
    throw Error("--target must be three finite numbers X Y Z");
  if (!(std::isfinite(a.dt) && a.dt >= 0)) throw Error("--dt must be a finite number > 0 (the time of one TIMESTEP)");
  if (a.every < 1) throw Error("--every must be ≥ 1");
  if (a.first < 0) throw Error("--first must be a frame index ≥ 0");
  if (a.last >= 0 && a.last < a.first)
    throw Error("--last " + std::to_string(a.last) + " comes before --first " + std::to_string(a.first));
  if (!a.png && !a.mp4) throw Error("nothing to write: --no-png and --no-mp4 together");
  if (!a.bins.empty() && (a.bins.size() != 2 || a.bins[0] < 1 || a.bins[1] < 1 || a.bins[0] > 4096 || a.bins[1] > 4096))
    throw Error("--bins must be two integers NX NY, each in 1..4096");
  if (!a.slab.empty() && (a.slab.size() != 2 || !std::isfinite(a.slab[0]) || !std::isfinite(a.slab[1]) ||
                          !(a.slab[0] < a.slab[1])))
    throw Error("--slab must be two finite numbers LO HI with LO < HI (coordinates across the field plane)");
  if (a.range_mode != "run" && a.range_mode != "frame")
    throw Error("--range-mode " + a.range_mode + " is not allowed; allowed: run, frame");
  if (!a.annotations && !a.panels.empty())
    throw Error("--no-annotations draws one bare picture; it takes no --panels");
  if (a.panels.empty()) {
    if (!a.layout.empty()) throw Error("--layout needs --panels (e.g. --panels particles,density,temperature,streamlines)");
    if (!a.map_ranges.empty()) throw Error("--map-range needs --panels with that map panel (e.g. --panels particles,density)");
    if (!a.plane.empty() || !a.slab.empty()) throw Error("--plane and --slab choose the field panels' plane; they need --panels");
  }
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
    for (const auto& spec : a.map_ranges) {
      // panel=lo,hi
      const auto eq = spec.find('='), comma = spec.find(',', eq == std::string::npos ? 0 : eq);
      double lo = 0, hi = 0;
      if (eq == std::string::npos || comma == std::string::npos ||
          !io::parse_double(spec.substr(eq + 1, comma - eq - 1), lo) || !io::parse_double(spec.substr(comma + 1), hi))
        throw Error("--map-range " + spec + ": expected PANEL=LO,HI (e.g. density=0.7,0.9)");
      render::set_fixed_range(*layout, spec.substr(0, eq), lo, hi);
    }
  } else if (a.annotations) {
    // One particle picture with what a reader needs to read it: colour bar (or legend for
    // categories) and the time/step caption.
    layout = render::make_layout(1, 1, std::vector<std::string>{"particles"});
  }
  const bool has_fields = layout && std::any_of(layout->panels.begin(), layout->panels.end(), [](const auto& p) {
                            return p.kind != render::PanelKind::particles;
                          });

  auto reader = io::open_particle_file(a.input);
  core::ParticleFrame frame;
  std::int64_t index = 0;  // source index of the frame in `frame`
  if (!reader->next(frame)) throw Error("'" + a.input + "' holds no frame");
  while (index < a.first) {
    if (!next_frame(*reader, frame, index + 1))
      throw Error("--first " + std::to_string(a.first) + ": '" + a.input + "' holds only " + std::to_string(index + 1) +
                  " complete frames (0.." + std::to_string(index) + ")");
    ++index;
  }

  // Option values, the colour attribute and the GL context are checked before anything is
  // created on disk.
  const std::string attribute = a.colour_by.empty() ? default_colour_attribute(frame) : a.colour_by;
  render::Snapshot snapshot;
  to_snapshot(frame, attribute, snapshot);  // throws naming the file's columns
  const render::Colormap colormap = render::Colormap::by_name(
      !a.colormap.empty() ? a.colormap : snapshot.attribute_categorical && !has_fields ? "tab10" : "viridis");
  const render::Backend backend = render::parse_backend(a.backend);
  core::BinPlane plane = core::BinPlane::xy;
  std::string plane_name = "xy";
  if (has_fields) {
    if (frame.dim == 2 && !a.plane.empty() && a.plane != "xy") throw Error("--plane " + a.plane + ": a 2D file has only the xy plane");
    if (frame.dim == 2 && !a.slab.empty()) throw Error("--slab is for 3D files: a 2D file has no depth to cut");
    plane_name = !a.plane.empty() ? a.plane : frame.dim == 3 ? "xz" : "xy";
    plane = field_plane(plane_name);
  }
  if (frame.dim == 2 && a.distance > 0) throw Error("--distance is for 3D files; a 2D view takes --zoom and --target");
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
  style.camera.zoom = a.zoom;
  if (!a.target.empty()) style.camera.target = Eigen::Vector3d(a.target[0], a.target[1], a.target[2]);
  if (a.distance > 0) style.camera.distance = a.distance;
  // The camera and the colour range stay fixed for the whole video, taken from the first
  // frame that has particles (or a box; or --range), so frames can be compared with one
  // another. A `fix pour` dump starts empty: its first frame fixes neither.
  Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  bool bounds_fixed = false;
  std::optional<std::array<int, 2>> bins;  // the field grid, once fixed
  if (!a.range.empty()) style.range = std::pair{a.range[0], a.range[1]};

  std::fprintf(stderr, "grainflow: %s (%s, %s) → %s  [%s, %dx%d, colour by %s]\n", a.input.c_str(),
               std::string(reader->format()).c_str(), frame.dim == 3 ? "3D spheres" : "2D disks", dir.c_str(),
               ctx->backend().c_str(), a.size[0], a.size[1], attribute.empty() ? "(none)" : attribute.c_str());
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_report = start;
  std::int64_t written = 0;
  // Ctrl-C / SIGTERM as in `grainflow run`: stop after the frame at hand, finish the MP4
  // and keep the frames written so far.
  InterruptGuard interrupts;
  bool interrupted = false;
  for (;;) {
    if (stop_requested()) {
      interrupted = true;
      break;
    }
    if ((index - a.first) % a.every == 0) {
      if (!bounds_fixed) {
        frame_bounds(frame, lo, hi);
        bounds_fixed = frame.has_box || frame.size() > 0;
      }
      to_snapshot(frame, attribute, snapshot);
      if (!a.periodic_images) snapshot.periodic = {false, false, false};
      if (!style.range && !snapshot.attribute_categorical && !snapshot.attribute.empty())
        style.range = render::finite_range(snapshot.attribute);
      snapshot.lo = lo;
      snapshot.hi = hi;
      const double time = frame_time(frame, a.dt);
      snapshot.time = std::isfinite(time) ? time : double(index);
      // The grid is fixed for the whole video, like the camera: by --bins, else from the
      // first frame with particles (an empty frame has no diameter to go by, nor fields).
      if (has_fields && !bins && (!a.bins.empty() || frame.size() > 0)) {
        bins = a.bins.empty() ? default_bins(frame, lo, hi, plane) : std::array{a.bins[0], a.bins[1]};
        std::fprintf(stderr, "grainflow: fields on %d × %d bins of the %s plane%s; temperature map: %s\n", (*bins)[0],
                     (*bins)[1], plane_name.c_str(), a.bins.empty() && frame.dim == 3 ? " (no finer than two diameters)" : "",
                     file_field_units(frame).temperature_label.c_str());
      }
      snapshot.fields_pending.clear();
      if (bins) {
        add_binned_fields(frame, lo, hi, *bins, plane, a.slab, snapshot);
      } else if (has_fields) {
        snapshot.fields.clear();
        snapshot.velocity.reset();
        snapshot.fields_pending = "no particles yet";
      }
      set_labels(frame, index, time, bins ? &*bins : nullptr, snapshot);
      // Frames are named by their index in the file, so --first/--every keep its numbering.
      output->consume(layout ? renderer.render(snapshot, style, *layout) : renderer.render(snapshot, style), index,
                      snapshot.time);
      // An empty frame (a pour's first) has nothing to scale a map by: the first frame
      // with particles fixes the ranges.
      if (layout && a.range_mode == "run" && frame.size() > 0)
        render::keep_drawn_ranges(*layout, renderer.last_panel_ranges());
      ++written;
    }
    const auto now = clock::now();
    if (now - last_report > std::chrono::seconds(2)) {
      const double s = std::chrono::duration<double>(now - start).count();
      std::fprintf(stderr, "grainflow: %lld frames, %.1f frames/s\n", static_cast<long long>(written), written / s);
      last_report = now;
    }
    if (a.last >= 0 && index >= a.last) break;
    if (!next_frame(*reader, frame, index + 1)) break;
    ++index;
  }
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
  cmd->add_option("--colormap", args->colormap,
                  "Colour map: " + joined(render::Colormap::names(), "|") +
                      " (default: tab10 for categories such as type on particles alone, else viridis)");
  cmd->add_option("--range", args->range, "Colour range LO HI (default: the first frame's range)")->expected(2);
  cmd->add_option("--msaa", args->msaa, "Multisample count (default 4 for 3D, 0 for 2D)");
  cmd->add_option("--fps", args->fps, "Video frame rate")->capture_default_str();
  cmd->add_option("--crf", args->crf, "H.264 quality, 0 (lossless) .. 51")->capture_default_str();
  cmd->add_option("--preset", args->preset, "x264 preset (ultrafast … veryslow)")->capture_default_str();
  cmd->add_option("--every", args->every, "Render every N-th frame from --first (frames keep their file index)")
      ->capture_default_str();
  cmd->add_option("--first", args->first, "First frame to render: its index in the file, from 0")->capture_default_str();
  cmd->add_option("--last", args->last, "Last frame to render (its index in the file; -1: to the end)")
      ->capture_default_str();
  cmd->add_option("--dt", args->dt, "Time of one TIMESTEP: the caption's time is TIMESTEP × DT (when the file gives no time)");
  cmd->add_option("--azimuth", args->azimuth, "3D camera azimuth, degrees")->capture_default_str();
  cmd->add_option("--elevation", args->elevation, "3D camera elevation, degrees")->capture_default_str();
  cmd->add_flag("--orthographic", args->orthographic, "3D: orthographic instead of perspective camera");
  cmd->add_option("--zoom", args->zoom, "Camera zoom (> 1 closer; 2D: shows 1/ZOOM of the box)")->capture_default_str();
  cmd->add_option("--target", args->target, "Point the camera looks at (2D: the view's centre): X Y Z; default: the box centre")
      ->expected(3);
  cmd->add_option("--distance", args->distance, "3D: camera distance from the target (default: the box fits)");
  cmd->add_flag("!--no-periodic-images", args->periodic_images,
                "do not draw particles across the periodic edges/faces the file declares (LAMMPS pp, XYZ pbc) on both sides");
  cmd->add_flag("!--no-annotations", args->annotations,
                "One bare picture: no title, colour bar, legend or time caption");
  cmd->add_flag("!--no-png", args->png, "Do not write the PNG sequence");
  cmd->add_flag("!--no-mp4", args->mp4, "Do not write the MP4");
  cmd->add_flag("--force", args->force, "Replace frames already in the output folder");
  cmd->add_option("--panels", args->panels,
                  "Panels of each frame, filled row by row: " + joined(render::panel_names(), ", ") +
                      " (fields binned from the particles on --plane; 3D: averaged across it, within --slab)")
      ->delimiter(',');
  cmd->add_option("--plane", args->plane, "Plane of the field panels: xy|xz|yz (default: xy for 2D, xz for 3D files)");
  cmd->add_option("--slab", args->slab, "3D field panels: only particles with LO ≤ coordinate across the plane < HI")
      ->expected(2);
  cmd->add_option("--range-mode", args->range_mode,
                  "Colour ranges of the map panels: run (each kept from the first frame that draws it) or frame "
                  "(each frame's own 2nd–98th percentiles)")
      ->capture_default_str();
  cmd->add_option("--map-range", args->map_ranges, "Fixed colour range of a map panel: PANEL=LO,HI (repeatable), "
                                                   "e.g. --map-range density=0.7,0.9");
  cmd->add_option("--bins", args->bins,
                  "Bins of the field grid: NX NY (default: 2D files 60 × 60; 3D files no finer than two of the "
                  "largest diameters of the first frame with particles)")
      ->expected(2);
  cmd->add_option("--layout", args->layout, "Panel grid: COLS ROWS (default: near-square for the panels)")
      ->expected(2);
  cmd->callback([args, &status] { status = run_render(*args); });
}

}  // namespace grainflow::scenes
