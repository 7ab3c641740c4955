// `grainflow run SCENE.toml -o DIR [--set key=value …]`: validates the scene, runs its
// engine, and writes DIR/scene.toml (effective scene), frames/*.png, <name>.mp4,
// stats.csv, particles.xyz (optional) and run.json. A frame is drawn every exposure τ_E
// (sample.exposure). Ctrl-C finishes cleanly: outputs hold what was computed and
// run.json says "interrupted".
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/xyz_writer.hpp"
#include "engine/dem/simulation.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "render/output/fan_out_sink.hpp"
#include "render/panel_layout.hpp"
#include "render/output/mp4_sink.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "scenes/src/cli/commands.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/run/interrupt.hpp"
#include "scenes/src/run/progress.hpp"
#include "scenes/src/run/run_folder.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/outputs/stats_csv.hpp"

namespace grainflow::scenes {
namespace fs = std::filesystem;
namespace {

struct RunArgs {
  std::string scene;
  std::string out_dir;
  std::vector<std::string> overrides;
  bool force = false;
  int threads = 0;  // 0: as OMP_NUM_THREADS says, else all cores
};

render::Rgb parse_colour(const std::string& hex) {
  // The schema has already checked "#rrggbb" / "#rrggbbaa".
  auto byte = [&](int i) { return float(std::stoi(hex.substr(std::size_t(1 + 2 * i), 2), nullptr, 16)) / 255.0f; };
  return {byte(0), byte(1), byte(2)};
}

// The caption line under the panels: title, time, N, exposure, stream velocity.
std::string caption(const Scene& scene, const render::Snapshot& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "t = %.4g   N = %zu   τ_E = %g", s.time, s.size(), scene.get<double>("sample.exposure"));
  std::string text = buf;
  if (s.reference_velocity) {
    std::snprintf(buf, sizeof buf, "   U = %g", s.reference_velocity->norm());
    text += buf;
  }
  const std::string title = scene.get<std::string>("run.title");
  return title.empty() ? text : title + "   " + text;
}

// Particle file frame from a snapshot, so OVITO/ParaView get positions and radii.
void to_particle_frame(const render::Snapshot& s, core::ParticleFrame& f) {
  f.clear();
  f.dim = s.dim;
  f.time = s.time;
  f.has_box = true;
  f.box_lo = s.lo;
  f.box_hi = s.hi;
  f.periodic = s.periodic;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float* p = &s.pos_radius[4 * i];
    f.id.push_back(std::int64_t(i + 1));
    f.position.emplace_back(p[0], p[1], p[2]);
    f.radius.push_back(p[3]);
    f.type.push_back(1);
  }
  if (!s.attribute.empty())
    f.extra.emplace_back(s.attribute_name, std::vector<double>(s.attribute.begin(), s.attribute.end()));
}

int run_scene(const RunArgs& a) {
  const Scene scene = load_scene(a.scene, a.overrides);
  if (a.threads > 0) dem::set_thread_count(a.threads);
  if (scene.get<bool>("output.fields"))
    throw Error("output.fields = true: field files are not written yet; allowed: false");
  if (scene.get<double>("output.checkpoint_every") > 0)
    throw Error("output.checkpoint_every > 0: checkpoints are not written by `grainflow run` yet; allowed: 0");
  const auto grid = scene.get<std::array<int, 2>>("render.layout");
  const render::FrameLayout layout =
      render::make_layout(grid[0], grid[1], scene.get<std::vector<std::string>>("render.panels"));

  const EngineEntry* engine = nullptr;
  for (const auto& e : engines())
    if (e.name == scene.engine()) engine = &e;
  if (!engine) throw Error("unknown engine '" + scene.engine() + "'");

  const RunFolder folder = RunFolder::open(a.out_dir, a.force ? RunFolderMode::Force : RunFolderMode::Fresh);
  write_effective_scene(scene, folder.file("scene.toml"));

  // Everything that can fail on configuration is set up before the first step.
  std::unique_ptr<EngineRunner> runner = engine->make_runner(scene);
  std::string notice;
  auto ctx = render::create_context(render::parse_backend(scene.get<std::string>("render.backend")), &notice);
  if (!notice.empty()) std::fprintf(stderr, "grainflow: %s\n", notice.c_str());
  const auto size = scene.get<std::array<int, 2>>("render.size");
  render::FrameRenderer renderer(*ctx, size[0], size[1], int(scene.get<std::int64_t>("render.msaa")));
  render::FrameStyle style;
  style.background = parse_colour(scene.get<std::string>("render.background"));
  style.colormap = render::Colormap::by_name(scene.get<std::string>("render.colormap"));
  const std::string colour_by = scene.get<std::string>("render.color_by");
  std::optional<std::pair<double, double>> fixed_range;
  if (auto r = scene.find<std::array<double, 2>>("render.range")) fixed_range = std::make_pair((*r)[0], (*r)[1]);

  std::vector<std::unique_ptr<render::FrameSink>> sinks;
  if (scene.get<bool>("output.png")) sinks.push_back(std::make_unique<render::PngSequenceSink>(folder.frames_dir()));
  const std::string name = fs::path(a.scene).stem().string();
  if (scene.get<bool>("output.mp4")) {
    render::Mp4Options opt;
    opt.fps = int(scene.get<std::int64_t>("output.fps"));
    opt.crf = int(scene.get<std::int64_t>("output.crf"));
    opt.preset = scene.get<std::string>("output.preset");
    sinks.push_back(std::make_unique<render::Mp4Sink>(folder.file(name + ".mp4"), opt));
  }
  const auto output = render::parallel_sinks(std::move(sinks));
  std::optional<io::XyzWriter> particles;
  if (scene.get<bool>("output.particles")) particles.emplace(folder.file("particles.xyz").string());
  StatsCsv stats(folder.file("stats.csv"), runner->stats_columns());
  runner->open_outputs(folder.dir());

  RunRecord record = make_run_record(scene);
  record.backend = ctx->backend() + " (" + ctx->gl_renderer() + ")";
  record.status = RunStatus::Running;
  write_run_record(record, folder.file("run.json"));

  const bool by_steps = scene.has("run.steps") && scene.get<std::int64_t>("run.steps") > 0;
  const double target = by_steps ? double(scene.get<std::int64_t>("run.steps")) : scene.get<double>("run.until");
  const double exposure = scene.get<double>("sample.exposure");
  const double stats_every = scene.get<double>("output.stats_every") > 0 ? scene.get<double>("output.stats_every")
                                                                          : exposure;
  ProgressReporter::Options popt;
  popt.target = target;
  popt.label = by_steps ? "step" : "t";
  popt.work_unit = runner->work_unit();
  ProgressReporter progress(popt);

  InterruptGuard interrupts;
  render::Snapshot snapshot;
  core::ParticleFrame pframe;
  std::int64_t frame_index = 0;
  // Frame and stats times are t0 + k·interval (not accumulated sums, which drift).
  const double t0 = runner->time();
  std::int64_t frames_due = 0, stats_due = 1;
  auto next_frame = [&] { return t0 + double(frames_due) * exposure; };
  auto next_stats = [&] { return t0 + double(stats_due) * stats_every; };
  double engine_seconds = 0;  // wall time inside the engine, for its own throughput
  const auto wall_start = std::chrono::steady_clock::now();
  auto emit_frame = [&] {
    runner->snapshot(colour_by, snapshot);
    // One colour range for the whole video (render.range, or the first frame's), so frames compare.
    if (frame_index == 0 && !snapshot.attribute.empty())
      style.range = fixed_range ? *fixed_range : render::finite_range(snapshot.attribute);
    snapshot.caption = caption(scene, snapshot);
    output->consume(renderer.render(snapshot, style, layout), frame_index++, snapshot.time);
    if (particles) {
      to_particle_frame(snapshot, pframe);
      particles->write(pframe);
    }
  };
  auto done = [&] { return by_steps ? double(runner->steps_done()) : runner->time(); };

  RunStatus status = RunStatus::Complete;
  try {
    emit_frame();
    ++frames_due;
    // Advance in slices of at most 1/20 exposure so progress and Ctrl-C stay responsive.
    const double slice = exposure / 20;
    const std::uint64_t step_slice = 1000;
    while (done() < target) {
      if (stop_requested()) {
        status = RunStatus::Interrupted;
        break;
      }
      const auto engine_start = std::chrono::steady_clock::now();
      if (by_steps) runner->advance_steps(std::min<std::uint64_t>(step_slice, std::uint64_t(target - done())));
      else runner->advance_to(std::min({runner->time() + slice, next_frame(), next_stats(), target}));
      engine_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - engine_start).count();
      const double t = runner->time();
      const double eps = 1e-9 * std::max(1.0, std::abs(t));
      if (t >= next_stats() - eps) {
        // Rows carry their scheduled time when the engine stopped there up to round-off.
        stats.row(std::abs(t - next_stats()) <= eps ? next_stats() : t, runner->stats_row());
        while (next_stats() <= t + eps) ++stats_due;
      }
      if (t >= next_frame() - eps) {
        emit_frame();
        while (next_frame() <= t + eps) ++frames_due;
      }
      progress.update(done(), runner->work());
    }
    progress.finish(done(), runner->work());
    output->finish();
    stats.finish();
    runner->finish_outputs();
    if (particles) particles->close();
  } catch (const std::exception& e) {
    record.status = RunStatus::Failed;
    record.error = e.what();
    record.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    write_run_record(record, folder.file("run.json"));
    throw;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  record.status = status;
  record.wall_time_s = wall;
  record.sim_time = runner->time();
  record.frames = frame_index;
  // The engine's own rate (time inside the engine) and the whole run's, drawing included.
  record.throughput = {{runner->work_unit(), runner->work() / std::max(engine_seconds, 1e-9), runner->work_unit() + "/s"},
                       {runner->work_unit() + "_overall", runner->work() / wall, runner->work_unit() + "/s"},
                       {"frames", double(frame_index) / wall, "frames/s"}};
  record.figures = runner->figures();
  record.state_digest = runner->state_digest();
  write_run_record(record, folder.file("run.json"));
  std::printf("%s: %lld frames, t = %.6g, engine %.3g %s/s, %.1f s wall → %s\n",
              status == RunStatus::Complete ? "complete" : "interrupted", static_cast<long long>(frame_index),
              runner->time(), runner->work() / std::max(engine_seconds, 1e-9), runner->work_unit().c_str(), wall,
              folder.dir().c_str());
  return status == RunStatus::Complete ? 0 : 130;
}

}  // namespace

void setup_run_command(CLI::App& app, int& status) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run a scene file: simulate, draw every exposure, write the run folder");
  cmd->add_option("scene", args->scene, "Scene file (TOML), e.g. scenes/disks_box.toml")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->out_dir, "Run folder to create")->required();
  cmd->add_option("--set", args->overrides, "Override a scene key: section.key=value (repeatable)")
      ->allow_extra_args(false);
  cmd->add_flag("--force", args->force, "Replace the results of a previous run in the folder");
  cmd->add_option("--threads", args->threads,
                  "Threads of the DEM engine (default: OMP_NUM_THREADS, else all cores; results do not depend on it)")
      ->check(CLI::PositiveNumber);
  cmd->callback([args, &status] { status = run_scene(*args); });
}

}  // namespace grainflow::scenes
