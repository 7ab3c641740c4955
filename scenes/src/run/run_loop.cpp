#include "scenes/src/run/run_loop.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "render/output/fan_out_sink.hpp"
#include "render/panel_layout.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/outputs/stats_csv.hpp"
#include "scenes/src/run/interrupt.hpp"
#include "scenes/src/run/progress.hpp"
#include "scenes/src/run/render_keys.hpp"
#include "scenes/src/run/run_folder.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

render::Rgb parse_colour(const std::string& hex) {
  // The schema has already checked "#rrggbb" / "#rrggbbaa".
  auto byte = [&](int i) { return float(std::stoi(hex.substr(std::size_t(1 + 2 * i), 2), nullptr, 16)) / 255.0f; };
  return {byte(0), byte(1), byte(2)};
}

// The caption line under the panels: title, time, N, exposure, stream velocity.
std::string caption(const std::string& title, double exposure, const render::Snapshot& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "t = %.4g   N = %zu   τ_E = %g", s.time, s.size(), exposure);
  std::string text = buf;
  if (s.reference_velocity) {
    std::snprintf(buf, sizeof buf, "   U = %g", s.reference_velocity->norm());
    text += buf;
  }
  return title.empty() ? text : title + "   " + text;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int run_scene(const Scene& scene, const RunOptions& opt) {
  // Everything decided by the scene alone is checked before the folder exists.
  const auto grid = scene.get(render_keys::layout);
  const render::FrameLayout layout = render::make_layout(grid[0], grid[1], scene.get(render_keys::panels));
  const EngineEntry* engine = find_engine(scene.engine());
  if (!engine) throw Error("unknown engine '" + scene.engine() + "'");

  const RunFolder folder = RunFolder::open(opt.dir, opt.force ? RunFolderMode::Force : RunFolderMode::Fresh);
  write_effective_scene(scene, folder.file("scene.toml"));

  // Everything that can fail on configuration is set up before the first step.
  std::unique_ptr<EngineRunner> runner = engine->make_runner(scene);
  std::string notice;
  const std::string backend = scene.get(render_keys::backend);
  auto ctx = render::create_context(render::parse_backend(backend), &notice);
  if (!notice.empty()) std::fprintf(stderr, "grainflow: %s\n", notice.c_str());
  const auto size = scene.get(render_keys::size);
  render::FrameRenderer renderer(*ctx, size[0], size[1], scene.get(render_keys::msaa));
  render::FrameStyle style;
  style.background = parse_colour(scene.get(render_keys::background));
  style.colormap = render::Colormap::by_name(scene.get(render_keys::colormap));
  const std::string colour_by = scene.get(render_keys::color_by);
  const std::optional<std::array<double, 2>> fixed_range = scene.find(render_keys::range);
  const std::string title = scene.get(run_keys::title);

  // The outputs: the table's, then the engine's own (DEM: pair.csv).
  const OutputContext octx{scene, folder.dir(), opt.name, runner->stats_columns()};
  std::vector<std::unique_ptr<render::FrameSink>> image_sinks;
  std::vector<std::unique_ptr<RunOutput>> data;
  for (const auto& o : outputs()) {
    if (o.open_image) {
      if (auto sink = o.open_image(octx)) image_sinks.push_back(std::move(sink));
    } else if (auto out = o.open_data(octx)) {
      data.push_back(std::move(out));
    }
  }
  // The engine's files go before run.json, the table's last row, which records them done.
  for (auto& out : runner->open_outputs(octx)) data.insert(data.end() - 1, std::move(out));
  const bool draw = !image_sinks.empty();
  const auto images = render::parallel_sinks(std::move(image_sinks));

  RunRecord record = make_run_record(scene);
  record.backend = ctx->backend() + " (" + ctx->gl_renderer() + ")";
  record.status = RunStatus::Running;
  for (auto& out : data) out->start(record);

  const bool by_steps = scene.has(run_keys::steps);
  const double target = by_steps ? double(scene.get(run_keys::steps)) : scene.get(run_keys::until);
  const double exposure = scene.get(sample_keys::exposure);
  const double stats_every = scene.get(stats_keys::every) > 0 ? scene.get(stats_keys::every) : exposure;
  ProgressReporter::Options popt;
  popt.target = target;
  popt.label = by_steps ? "step" : "t";
  popt.work_unit = runner->work_unit();
  ProgressReporter progress(popt);

  InterruptGuard interrupts;
  render::Snapshot snapshot;
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
      style.range = fixed_range ? std::make_pair((*fixed_range)[0], (*fixed_range)[1])
                                : render::finite_range(snapshot.attribute);
    snapshot.caption = caption(title, exposure, snapshot);
    if (draw) images->consume(renderer.render(snapshot, style, layout), frame_index, snapshot.time);
    for (auto& out : data) out->frame(frame_index, snapshot);
    ++frame_index;
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
      engine_seconds += seconds_since(engine_start);
      const double t = runner->time();
      const double eps = 1e-9 * std::max(1.0, std::abs(t));
      if (t >= next_stats() - eps) {
        // Rows carry their scheduled time when the engine stopped there up to round-off.
        const double row_time = std::abs(t - next_stats()) <= eps ? next_stats() : t;
        const std::vector<double> row = runner->stats_row();
        for (auto& out : data) out->stats(row_time, row);
        while (next_stats() <= t + eps) ++stats_due;
      }
      if (t >= next_frame() - eps) {
        emit_frame();
        while (next_frame() <= t + eps) ++frames_due;
      }
      progress.update(done(), runner->work());
    }
    progress.finish(done(), runner->work());
    images->finish();
    const double wall = seconds_since(wall_start);
    record.status = status;
    record.wall_time_s = wall;
    record.sim_time = runner->time();
    record.frames = frame_index;
    // The engine's own rate (time inside the engine) and the whole run's, drawing included.
    const std::string unit = runner->work_unit();
    record.throughput = {{unit, runner->work() / std::max(engine_seconds, 1e-9), unit + "/s"},
                         {unit + "_overall", runner->work() / wall, unit + "/s"},
                         {"frames", double(frame_index) / wall, "frames/s"}};
    record.figures = runner->figures();
    record.state_digest = runner->state_digest();
    for (auto& out : data) out->finish(record);
  } catch (const std::exception& e) {
    record.status = RunStatus::Failed;
    record.error = e.what();
    record.wall_time_s = seconds_since(wall_start);
    for (auto& out : data) out->fail(record);
    throw;
  }
  if (!opt.quiet)
    std::printf("%s: %lld frames, t = %.6g, engine %.3g %s/s, %.1f s wall → %s\n",
                status == RunStatus::Complete ? "complete" : "interrupted", static_cast<long long>(frame_index),
                runner->time(), runner->work() / std::max(engine_seconds, 1e-9), runner->work_unit().c_str(),
                record.wall_time_s, folder.dir().c_str());
  return status == RunStatus::Complete ? 0 : 130;
}

}  // namespace grainflow::scenes
