#include "scenes/src/run/run_loop.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <tuple>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/checkpoint_file.hpp"
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
#include "scenes/src/outputs/video_keys.hpp"
#include "scenes/src/run/checkpoints.hpp"
#include "scenes/src/run/interrupt.hpp"
#include "scenes/src/run/progress.hpp"
#include "scenes/src/run/render_keys.hpp"
#include "scenes/src/run/run_folder.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"
#include "scenes/src/studies/study_table.hpp"

namespace grainflow::scenes {
namespace {

render::Rgb parse_colour(const std::string& hex) {
  // The schema has already checked "#rrggbb" / "#rrggbbaa".
  auto byte = [&](int i) { return float(std::stoi(hex.substr(std::size_t(1 + 2 * i), 2), nullptr, 16)) / 255.0f; };
  return {byte(0), byte(1), byte(2)};
}

}  // namespace

std::string frame_caption(const std::string& title, double exposure, const render::Snapshot& s) {
  char buf[256];
  const std::string unit = s.time_unit.empty() ? "" : " " + s.time_unit;
  std::snprintf(buf, sizeof buf, "t = %.4g%s   N = %zu   τ_E = %g%s", s.time, unit.c_str(), s.size(), exposure,
                unit.c_str());
  std::string text = buf;
  if (s.reference_velocity) {
    std::snprintf(buf, sizeof buf, "   U = %g", s.reference_velocity->norm());
    text += buf;
  }
  for (const auto& [k, v] : s.labels) text += "   " + k + " = " + v;
  return title.empty() ? text : title + "   " + text;
}

namespace {

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
        exposure_(scene.get(sample_keys::exposure)),
        run_ranges_(scene.get(render_keys::range_mode) == "run"),
        fit_grid_(!scene.has(render_keys::layout)) {
    const auto map_filter = scene.get(render_keys::filter) == "nearest" ? render::FieldFilter::nearest
                                                                        : render::FieldFilter::bilinear;
    const bool with_stream = scene.get(render_keys::streamlines_frame) == "stream";
    for (auto& p : layout_.panels) {
      p.filter = map_filter;
      p.streamlines.relative_to_reference = with_stream;
    }
    // render.ranges.<panel>: fixed from the start (validation refused ranges of panels
    // that are not drawn).
    for (std::string_view ranged : render_keys::ranged_panels())
      if (auto r = scene.find(render_keys::panel_range(ranged))) render::set_fixed_range(layout_, ranged, (*r)[0], (*r)[1]);
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
  // The run's GL context, for outputs that draw pictures of their own (study plots).
  render::GlContext& context() { return *ctx_; }

  // Adds the caption; the first frame with a colour attribute fixes the colour range for
  // the whole video (render.range, or its own), so frames compare.
  void prepare(render::Snapshot& s) {
    if (!range_fixed_ && !s.attribute.empty()) {
      style_.range = fixed_range_ ? std::make_pair((*fixed_range_)[0], (*fixed_range_)[1])
                                  : render::finite_range(s.attribute);
      range_fixed_ = true;
    }
    s.caption = frame_caption(title_, exposure_, s);
  }
  const render::Image& draw(const render::Snapshot& s) {
    if (fit_grid_) {
      // The domain's width over height as drawn: the x–y plane in 2D; a 3D box is drawn in
      // perspective, about square.
      const Eigen::Vector3d extent = s.hi - s.lo;
      const double aspect = s.dim == 2 && extent.y() > 0 ? extent.x() / extent.y() : 1.0;
      std::tie(layout_.cols, layout_.rows) = render::fitted_grid(int(layout_.panels.size()), renderer_->width(),
                                                                 renderer_->height(), aspect, layout_.caption);
      fit_grid_ = false;
    }
    const render::Image& image = renderer_->render(s, style_, layout_);
    // "run": a panel's first drawn range is kept for every frame after it.
    if (run_ranges_) render::keep_drawn_ranges(layout_, renderer_->last_panel_ranges());
    return image;
  }
  // The colour range the first frame fixed: a resumed run draws with it too.
  void save(io::ArchiveWriter& w) const {
    w.tag("drawing");
    w.flag(range_fixed_);
    w.flag(style_.range.has_value());
    const auto range = style_.range.value_or(std::make_pair(0.0, 0.0));
    w.pod(range.first);
    w.pod(range.second);
    w.pod(std::uint64_t(layout_.panels.size()));
    for (const auto& p : layout_.panels) {
      w.flag(p.range.mode == render::FieldRange::Mode::fixed);
      w.pod(p.range.lo);
      w.pod(p.range.hi);
    }
  }
  void load(io::ArchiveReader& r) {
    r.tag("drawing");
    range_fixed_ = r.flag("the colour range flag");
    const bool has_range = r.flag("the colour range flag");
    const double lo = r.get<double>(), hi = r.get<double>();
    if (has_range) style_.range = std::make_pair(lo, hi);
    if (r.get<std::uint64_t>() != layout_.panels.size()) r.mismatch("another panel layout");
    for (auto& p : layout_.panels) {
      const bool fixed = r.flag("a panel's range flag");
      const double plo = r.get<double>(), phi = r.get<double>();
      if (fixed) p.range = render::FieldRange::fixed(plo, phi);
    }
  }

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
  bool run_ranges_;  // render.range_mode = "run"
  bool fit_grid_;    // no render.layout: the grid is fitted to the domain at the first frame
};

// The outputs of one run: the output table's (image sinks encode on threads of their
// own), then the engine's own files, before run.json, the table's last row, which
// records them done.
class RunOutputs {
public:
  RunOutputs(const OutputContext& ctx, EngineRunner& runner, render::GlContext& gl) {
    std::vector<std::unique_ptr<render::FrameSink>> sinks;
    for (const auto& o : outputs()) {
      if (o.open_image) {
        if (auto sink = o.open_image(ctx)) sinks.push_back(std::move(sink));
      } else if (auto out = o.open_data(ctx)) {
        data_.push_back(std::move(out));
      }
    }
    for (auto& out : runner.open_outputs(ctx)) data_.insert(data_.end() - 1, std::move(out));
    // The study ([study]) reads the rows as stats.csv has them and finishes before run.json.
    if (auto study = open_study_output(ctx, gl)) data_.insert(data_.end() - 1, std::move(study));
    draws_ = !sinks.empty();
    images_ = render::parallel_sinks(std::move(sinks));
  }
  // Whether any output takes pictures (else frames are not drawn at all).
  bool draws() const { return draws_; }
  void start(const RunRecord& r) {
    for (auto& o : data_) o->start(r);
  }
  void resume(io::ArchiveReader& in, const RunRecord& r) {
    for (auto& o : data_) o->resume(in, r);
  }
  // Every frame so far on disk as a prefix a resumed run continues (the MP4 closes its
  // encoder's stream here and opens another), then each data output's position.
  void checkpoint(io::ArchiveWriter& w) {
    images_->sync();
    for (auto& o : data_) o->checkpoint(w);
  }
  bool wants_particles() const {
    for (const auto& o : data_)
      if (o->wants_particles()) return true;
    return false;
  }
  void frame(std::int64_t index, const render::Snapshot& s, const render::Image* image,
             const core::ParticleFrame* particles) {
    if (image) images_->consume(*image, index, s.time);
    for (auto& o : data_) {
      o->frame(index, s);
      if (particles && o->wants_particles()) o->particles(index, *particles);
    }
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
      .at_least(0.0)
      .may_change_on_resume();
  s.table("run")
      .add_int(max_steps, 0,
               "engine work this invocation may do (ED: events, DEM: steps): reached, the run stops as "
               "\"interrupted\" with a checkpoint (0 = no limit)")
      .at_least(0)
      .may_change_on_resume();
  s.table("output")
      .add_float(checkpoint_every, 0.0,
                 "simulated time between checkpoints for `grainflow run --resume` (0 = only when interrupted and "
                 "at run.max_wall); the run keeps the last two",
                 "time units")
      .at_least(0.0)
      .may_change_on_resume();
  s.table("output")
      .add_float(video_seconds, 10.0,
                 "length of the MP4 when output.fps is not given: the frame rate is chosen from the number of "
                 "frames (1 to 60 frames/s)",
                 "s")
      .above(0.0);
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

std::optional<std::string> auto_fps_override(const Scene& scene) {
  // Read even when unused, so that the key counts as consumed in every scene.
  const double seconds = scene.get(loop_keys::video_seconds);
  if (scene.has(video_keys::fps)) return std::nullopt;
  const auto until = scene.find(run_keys::until);
  if (!until) return std::nullopt;
  // Frame 0 at t = 0, then one every exposure up to run.until.
  const double frames = std::floor(*until / scene.get(sample_keys::exposure)) + 1.0;
  const auto fps = std::int64_t(std::clamp(std::round(frames / seconds), 1.0, 60.0));
  return "output.fps=" + std::to_string(fps);
}

namespace {

// What the loop itself carries across a checkpoint.
struct LoopState {
  std::int64_t frame_index = 0;  // frames emitted
  std::int64_t frames_due = 0, stats_due = 1, checkpoints_due = 1;
  double t0 = 0;                 // frame and stats times are t0 + k·interval
  double engine_seconds = 0;     // wall time inside the engine, for its own throughput
  double wall_before = 0;        // wall time of the sessions before this one
  std::int64_t resumes = 0;
};

// `name`: the stem of the scene file the run started from, which names the MP4 (a
// resumed run reads DIR/scene.toml instead).
void save_loop(io::ArchiveWriter& w, const LoopState& st, const RunRecord& record, const std::string& name) {
  w.tag("loop");
  w.pod(st);
  w.string(record.started_utc);
  w.string(name);
  w.string(record.scene);
  w.pod(std::uint64_t(record.overrides.size()));
  for (const auto& o : record.overrides) w.string(o);
}

LoopState load_loop(io::ArchiveReader& r, RunRecord& record, std::string& name) {
  r.tag("loop");
  LoopState st = r.get<LoopState>();
  record.started_utc = r.string();
  name = r.string();
  // run.json keeps saying which scene file and --set made the run; a resume's own --set
  // (run.until, …) are added to them.
  const std::vector<std::string> resume_overrides = record.overrides;
  record.scene = r.string();
  const auto n = r.get<std::uint64_t>();
  if (n > r.left()) r.corrupt("a list of " + std::to_string(n) + " overrides");
  record.overrides.clear();
  for (std::uint64_t i = 0; i < n; ++i) record.overrides.push_back(r.string());
  for (const auto& o : resume_overrides) record.overrides.push_back(o + " (on resume)");
  return st;
}

}  // namespace

int run_scene(const Scene& scene, const RunOptions& opt) {
  // Everything decided by the scene alone is checked before the folder exists.
  // Without render.layout the grid is fitted to the domain at the first frame (FrameDrawing);
  // until then rows of up to 8 hold them.
  const auto panel_names = scene.get(render_keys::panels);
  const int n = int(panel_names.size());
  const auto grid = scene.find(render_keys::layout).value_or(std::array<int, 2>{std::min(n, 8), (n + 7) / 8});
  const render::FrameLayout layout = render::make_layout(int(grid[0]), int(grid[1]), panel_names);
  const EngineEntry* engine = find_engine(scene.engine());
  if (!engine) throw Error("unknown engine '" + scene.engine() + "'");

  // Everything that can fail on configuration is set up before the folder is touched.
  std::unique_ptr<EngineRunner> runner = engine->make_runner(scene);
  FrameDrawing drawing(scene, layout);

  const RunFolderMode mode = opt.resume ? RunFolderMode::Resume : opt.force ? RunFolderMode::Force : RunFolderMode::Fresh;
  RunFolder folder = RunFolder::open(opt.dir, mode);
  CheckpointStore checkpoints(folder);
  const std::uint64_t fingerprint = scene.fingerprint();  // the scene's text, hashed once a run
  const bool by_steps = scene.has(run_keys::steps);
  const double target = by_steps ? double(scene.get(run_keys::steps)) : scene.get(run_keys::until);
  auto done = [&] { return by_steps ? double(runner->steps_done()) : runner->time(); };

  std::optional<RunOutputs> outputs_opened;
  RunRecord record = make_run_record(scene);
  LoopState st;
  std::string ctx_name;  // the MP4's name
  try {
    std::optional<io::Checkpoint> resumed;
    std::optional<io::ArchiveReader> in;
    OutputContext ctx{scene, folder.dir(), opt.name, runner->stats_columns(),
                      [&folder](std::string_view name) { folder.claim(name); }, std::nullopt};
    if (opt.resume) {
      // The state first: a checkpoint that does not fit is refused before any file changes.
      resumed = checkpoints.read_latest(scene.engine(), fingerprint);
      in.emplace(resumed->payload, "checkpoint of " + folder.dir().string());
      st = load_loop(*in, record, ctx.name);
      drawing.load(*in);
      runner->load(*in);
      if (done() >= target)
        throw Error(fmt::format("nothing to resume in '{}': the run reached {} = {:.6g} already; allowed: a larger "
                                "--set run.{}=… to extend it",
                                folder.dir().string(), by_steps ? "step" : "t", done(), by_steps ? "steps" : "until"));
      ctx.resume_frames = st.frame_index;
      ++st.resumes;
    } else {
      folder.claim("scene.toml");
      write_effective_scene(scene, folder.file("scene.toml"));
      st.t0 = runner->time();
    }
    ctx_name = ctx.name;
    outputs_opened.emplace(ctx, *runner, drawing.context());
    record.backend = drawing.backend();
    record.status = RunStatus::Running;
    record.resumes = st.resumes;
    if (in) {
      outputs_opened->resume(*in, record);
      in->expect_end();
      std::fprintf(stderr, "grainflow: resuming at %s = %.6g (frame %lld) from %s\n", by_steps ? "step" : "t",
                   done(), static_cast<long long>(st.frame_index), folder.dir().c_str());
    } else {
      outputs_opened->start(record);
    }
  } catch (...) {
    // A failed start leaves no trace of this run: its files, and the folder if it was new
    // (a failed resume leaves the previous run's files as they were).
    outputs_opened.reset();
    folder.abandon();
    throw;
  }
  RunOutputs& out = *outputs_opened;

  const double exposure = scene.get(sample_keys::exposure);
  const double stats_every = scene.get(stats_keys::every) > 0 ? scene.get(stats_keys::every) : exposure;
  const double checkpoint_every = scene.get(loop_keys::checkpoint_every);
  ProgressReporter::Options popt;
  popt.target = target;
  popt.label = by_steps ? "step" : "t";
  popt.work_unit = runner->work_unit();
  ProgressReporter progress(popt);

  InterruptGuard interrupts;
  render::Snapshot snapshot;
  auto next_frame = [&] { return st.t0 + double(st.frames_due) * exposure; };
  auto next_stats = [&] { return st.t0 + double(st.stats_due) * stats_every; };
  auto next_checkpoint = [&] { return st.t0 + double(st.checkpoints_due) * checkpoint_every; };
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall = [&] { return st.wall_before + seconds_since(wall_start); };
  const bool wants_particles = out.wants_particles();
  core::ParticleFrame particles;
  auto emit_frame = [&] {
    runner->snapshot(drawing.colour_by(), snapshot);
    if (wants_particles) runner->particles(particles);
    drawing.prepare(snapshot);
    out.frame(st.frame_index++, snapshot, out.draws() ? &drawing.draw(snapshot) : nullptr,
              wants_particles ? &particles : nullptr);
  };
  std::string checkpoint_buffer;  // kept from one checkpoint to the next
  // Between two slices of the loop: a resumed run continues with the next slice exactly
  // as the uninterrupted run would have (slices do not depend on when checkpoints are
  // taken, so neither do the numbers).
  auto take_checkpoint = [&] {
    const auto t_start = std::chrono::steady_clock::now();
    io::ArchiveWriter w(std::move(checkpoint_buffer));
    LoopState saved = st;
    saved.wall_before = wall();
    save_loop(w, saved, record, ctx_name);
    drawing.save(w);
    runner->save(w);
    out.checkpoint(w);
    checkpoints.write({scene.engine(), fingerprint, runner->time(), st.frame_index, 0}, w.bytes());
    checkpoint_buffer = w.take();
    record.checkpoint_seconds += seconds_since(t_start);
    ++record.checkpoints;
  };

  RunStatus status = RunStatus::Complete;
  try {
    if (!opt.resume) {
      emit_frame();
      ++st.frames_due;
    }
    // Advance in slices of at most 1/20 exposure so progress and Ctrl-C stay responsive.
    const double slice = exposure / 20;
    const std::uint64_t step_slice = 1000;
    const double max_wall = scene.get(loop_keys::max_wall);
    const std::uint64_t max_steps = std::uint64_t(scene.get(loop_keys::max_steps));
    const std::uint64_t steps_at_start = runner->steps_done();
    // run.json is refreshed this often while running: after a SIGKILL it says how far the run got.
    constexpr double kRecordEvery = 10.0;
    auto last_record = std::chrono::steady_clock::now();
    while (done() < target) {
      if (stop_requested()) {
        status = RunStatus::Interrupted;
        break;
      }
      if (max_steps > 0 && runner->steps_done() - steps_at_start >= max_steps) {
        std::fprintf(stderr, "grainflow: run.max_steps = %llu reached, stopping\n",
                     static_cast<unsigned long long>(max_steps));
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
      st.engine_seconds += seconds_since(engine_start);
      const double t = runner->time();
      const double eps = 1e-9 * std::max(1.0, std::abs(t));
      if (t >= next_stats() - eps) {
        // Rows carry their scheduled time when the engine stopped there up to round-off.
        const double row_time = std::abs(t - next_stats()) <= eps ? next_stats() : t;
        out.stats(row_time, runner->stats_row());
        while (next_stats() <= t + eps) ++st.stats_due;
      }
      if (t >= next_frame() - eps) {
        emit_frame();
        while (next_frame() <= t + eps) ++st.frames_due;
      }
      if (checkpoint_every > 0 && t >= next_checkpoint() - eps && done() < target) {
        while (next_checkpoint() <= t + eps) ++st.checkpoints_due;
        take_checkpoint();
      }
      progress.update(done(), runner->work());
      if (seconds_since(last_record) >= kRecordEvery) {
        record.sim_time = runner->time();
        record.frames = st.frame_index;
        record.wall_time_s = wall();
        out.progress(record);
        last_record = std::chrono::steady_clock::now();
      }
    }
    progress.finish(done(), runner->work());
    runner->check_finite();
    // An interrupted run can always be resumed; a complete one can be extended (a larger
    // run.until) when it keeps checkpoints.
    if (status == RunStatus::Interrupted || checkpoint_every > 0) take_checkpoint();
    out.finish_images();
    record.status = status;
    record.wall_time_s = wall();
    record.sim_time = runner->time();
    record.frames = st.frame_index;
    // The engine's own rate (time inside the engine) and the whole run's, drawing included.
    const std::string unit = runner->work_unit();
    record.throughput = {{unit, runner->work() / std::max(st.engine_seconds, 1e-9), unit + "/s"},
                         {unit + "_overall", runner->work() / record.wall_time_s, unit + "/s"},
                         {"frames", double(st.frame_index) / record.wall_time_s, "frames/s"}};
    record.figures = runner->figures();
    record.state_digest = runner->state_digest();
    out.finish(record);
  } catch (const std::exception& e) {
    record.status = RunStatus::Failed;
    record.error = e.what();
    record.wall_time_s = wall();
    out.fail(record);
    throw;
  }
  if (!opt.quiet)
    std::printf("%s: %lld frames, t = %.6g, engine %.3g %s/s, %.1f s wall → %s\n",
                status == RunStatus::Complete ? "complete" : "interrupted", static_cast<long long>(st.frame_index),
                runner->time(), runner->work() / std::max(st.engine_seconds, 1e-9), runner->work_unit().c_str(),
                record.wall_time_s, folder.dir().c_str());
  if (const std::string a = runner->advice(); !a.empty()) {
    std::fflush(stdout);
    std::fprintf(stderr, "grainflow: %s\n", a.c_str());
  }
  return status == RunStatus::Complete ? 0 : 130;
}

}  // namespace grainflow::scenes
