#include "scenes/src/run/run_loop.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <initializer_list>
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
#include "scenes/src/scene/toml_text.hpp"

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

// Where a slice that would end at `to` stops: at the first due time (frame, stats row,
// end of run) it reaches, or comes within round-off of. Slices are summed, so `to` drifts
// off t0 + k·interval; a frame taken 1e-14 before its time would miss the events due then
// (the sampler closing its exposure) and show the previous exposure's fields.
double slice_end(double to, std::initializer_list<double> due) {
  std::optional<double> reached;
  for (double t : due)
    if (to >= t - 1e-9 * std::max(1.0, std::abs(t))) reached = reached ? std::min(*reached, t) : t;
  return reached ? *reached : to;
}

// The [render] keys turned into a GL context, a renderer, a frame style and a layout.
class FrameDrawing {
public:
  FrameDrawing(const Scene& scene, const render::FrameLayout& layout)
      : layout_(layout),
        colour_by_(scene.get(render_keys::color_by)),
        fixed_range_(scene.find(render_keys::range)),
        title_(scene.get(run_keys::title)),
        exposure_(scene.get(sample_keys::exposure)) {
    std::string notice;
    ctx_ = render::create_context(render::parse_backend(scene.get(render_keys::backend)), &notice);
    if (!notice.empty()) std::fprintf(stderr, "grainflow: %s\n", notice.c_str());
    const auto size = scene.get(render_keys::size);
    renderer_.emplace(*ctx_, size[0], size[1], scene.get(render_keys::msaa));
    style_.background = parse_colour(scene.get(render_keys::background));
    style_.colormap = render::Colormap::by_name(scene.get(render_keys::colormap));
  }
  const std::string& colour_by() const { return colour_by_; }
  std::string backend() const { return ctx_->backend() + " (" + ctx_->gl_renderer() + ")"; }

  // Adds the caption; the first frame with a colour attribute fixes the colour range for
  // the whole video (render.range, or its own), so frames compare.
  void prepare(render::Snapshot& s) {
    if (!range_fixed_ && !s.attribute.empty()) {
      style_.range = fixed_range_ ? std::make_pair((*fixed_range_)[0], (*fixed_range_)[1])
                                  : render::finite_range(s.attribute);
      range_fixed_ = true;
    }
    s.caption = caption(title_, exposure_, s);
  }
  const render::Image& draw(const render::Snapshot& s) { return renderer_->render(s, style_, layout_); }

private:
  render::FrameLayout layout_;
  std::string colour_by_;
  std::optional<std::array<double, 2>> fixed_range_;
  std::string title_;
  double exposure_;
  std::unique_ptr<render::GlContext> ctx_;
  std::optional<render::FrameRenderer> renderer_;
  render::FrameStyle style_;
  bool range_fixed_ = false;
};

// The outputs of one run: the output table's (image sinks encode on threads of their
// own), then the engine's own files, before run.json, the table's last row, which
// records them done.
class RunOutputs {
public:
  RunOutputs(const OutputContext& ctx, EngineRunner& runner) {
    std::vector<std::unique_ptr<render::FrameSink>> sinks;
    for (const auto& o : outputs()) {
      if (o.open_image) {
        if (auto sink = o.open_image(ctx)) sinks.push_back(std::move(sink));
      } else if (auto out = o.open_data(ctx)) {
        data_.push_back(std::move(out));
      }
    }
    for (auto& out : runner.open_outputs(ctx)) data_.insert(data_.end() - 1, std::move(out));
    draws_ = !sinks.empty();
    images_ = render::parallel_sinks(std::move(sinks));
  }
  // Whether any output takes pictures (else frames are not drawn at all).
  bool draws() const { return draws_; }
  void start(const RunRecord& r) {
    for (auto& o : data_) o->start(r);
  }
  void frame(std::int64_t index, const render::Snapshot& s, const render::Image* image) {
    if (image) images_->consume(*image, index, s.time);
    for (auto& o : data_) o->frame(index, s);
  }
  void stats(double time, std::span<const double> row) {
    for (auto& o : data_) o->stats(time, row);
  }
  void progress(const RunRecord& r) {
    for (auto& o : data_) o->progress(r);
  }
  void finish_images() { images_->finish(); }
  void finish(const RunRecord& r) {
    for (auto& o : data_) o->finish(r);
  }
  // Every output is told, whatever the others do: the first error (the one being thrown)
  // stays the one reported, later ones (run.json on a full disk, say) are printed.
  void fail(const RunRecord& r) noexcept {
    for (auto& o : data_) {
      try {
        o->fail(r);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "grainflow: also: %s\n", e.what());
      }
    }
  }

private:
  std::vector<std::unique_ptr<RunOutput>> data_;
  std::unique_ptr<render::FrameSink> images_;
  bool draws_ = false;
};

}  // namespace

namespace loop_keys {

void declare(Schema& s) {
  s.table("run")
      .add_float(max_wall, 0.0, "wall-clock limit: the run stops as \"interrupted\" when it is reached (0 = none)", "s")
      .at_least(0.0);
  s.add_check([](const Scene& sc, SceneCheck& c) {
    // Each frame is drawn and stored, each row written: a scene asking for 10^300 of them
    // (sample.exposure = 1e-300) is a mistake, not a run.
    constexpr double kMaxFrames = 1e7, kMaxRows = 1e8;
    const auto until = sc.find(run_keys::until);
    if (!until) return;
    const double exposure = sc.get(sample_keys::exposure);
    if (*until / exposure > kMaxFrames)
      c.fail(sample_keys::exposure.path, "run.until / sample.exposure = " + toml_float(*until / exposure) +
                                             " frames; allowed: at most 1e7 frames (a larger sample.exposure)");
    const double every = sc.get(stats_keys::every);
    if (every > 0 && *until / every > kMaxRows)
      c.fail(stats_keys::every.path, "run.until / output.stats_every = " + toml_float(*until / every) +
                                         " rows; allowed: at most 1e8 rows");
  });
}

}  // namespace loop_keys

int run_scene(const Scene& scene, const RunOptions& opt) {
  // Everything decided by the scene alone is checked before the folder exists.
  const auto grid = scene.get(render_keys::layout);
  const render::FrameLayout layout = render::make_layout(grid[0], grid[1], scene.get(render_keys::panels));
  const EngineEntry* engine = find_engine(scene.engine());
  if (!engine) throw Error("unknown engine '" + scene.engine() + "'");

  // Everything that can fail on configuration is set up before the folder is touched.
  std::unique_ptr<EngineRunner> runner = engine->make_runner(scene);
  FrameDrawing drawing(scene, layout);

  RunFolder folder = RunFolder::open(opt.dir, opt.force ? RunFolderMode::Force : RunFolderMode::Fresh);
  std::optional<RunOutputs> outputs_opened;
  RunRecord record = make_run_record(scene);
  try {
    folder.claim("scene.toml");
    write_effective_scene(scene, folder.file("scene.toml"));
    outputs_opened.emplace(OutputContext{scene, folder.dir(), opt.name, runner->stats_columns(),
                                         [&folder](std::string_view name) { folder.claim(name); }},
                           *runner);
    record.backend = drawing.backend();
    record.status = RunStatus::Running;
    outputs_opened->start(record);
  } catch (...) {
    // A failed start leaves no trace of this run: its files, and the folder if it was new.
    outputs_opened.reset();
    folder.abandon();
    throw;
  }
  RunOutputs& out = *outputs_opened;

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
    runner->snapshot(drawing.colour_by(), snapshot);
    drawing.prepare(snapshot);
    out.frame(frame_index++, snapshot, out.draws() ? &drawing.draw(snapshot) : nullptr);
  };
  auto done = [&] { return by_steps ? double(runner->steps_done()) : runner->time(); };

  RunStatus status = RunStatus::Complete;
  try {
    emit_frame();
    ++frames_due;
    // Advance in slices of at most 1/20 exposure so progress and Ctrl-C stay responsive.
    const double slice = exposure / 20;
    const std::uint64_t step_slice = 1000;
    const double max_wall = scene.get(loop_keys::max_wall);
    // run.json is refreshed this often while running: after a SIGKILL it says how far the run got.
    constexpr double kRecordEvery = 10.0;
    auto last_record = std::chrono::steady_clock::now();
    while (done() < target) {
      if (stop_requested()) {
        status = RunStatus::Interrupted;
        break;
      }
      if (max_wall > 0 && seconds_since(wall_start) >= max_wall) {
        std::fprintf(stderr, "grainflow: run.max_wall = %g s reached, stopping\n", max_wall);
        status = RunStatus::Interrupted;
        break;
      }
      const auto engine_start = std::chrono::steady_clock::now();
      if (by_steps) runner->advance_steps(std::min<std::uint64_t>(step_slice, std::uint64_t(target - done())));
      else runner->advance_to(slice_end(runner->time() + slice, {next_frame(), next_stats(), target}));
      engine_seconds += seconds_since(engine_start);
      const double t = runner->time();
      const double eps = 1e-9 * std::max(1.0, std::abs(t));
      if (t >= next_stats() - eps) {
        // Rows carry their scheduled time when the engine stopped there up to round-off.
        const double row_time = std::abs(t - next_stats()) <= eps ? next_stats() : t;
        out.stats(row_time, runner->stats_row());
        while (next_stats() <= t + eps) ++stats_due;
      }
      if (t >= next_frame() - eps) {
        emit_frame();
        while (next_frame() <= t + eps) ++frames_due;
      }
      progress.update(done(), runner->work());
      if (seconds_since(last_record) >= kRecordEvery) {
        record.sim_time = runner->time();
        record.frames = frame_index;
        record.wall_time_s = seconds_since(wall_start);
        out.progress(record);
        last_record = std::chrono::steady_clock::now();
      }
    }
    progress.finish(done(), runner->work());
    runner->check_finite();
    out.finish_images();
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
    out.finish(record);
  } catch (const std::exception& e) {
    record.status = RunStatus::Failed;
    record.error = e.what();
    record.wall_time_s = seconds_since(wall_start);
    out.fail(record);
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
