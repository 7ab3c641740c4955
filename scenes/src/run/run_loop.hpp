// The run loop of `grainflow run`: set everything up that can fail on configuration
// (engine, GL context, outputs) before the first step, then advance the engine in short
// slices, drawing a frame every exposure τ_E and a stats row every stats interval, until
// run.until / run.steps or Ctrl-C; every output is finished (or failed) at the end.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "render/snapshot.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

class Scene;

namespace loop_keys {
// Wall-clock limit of a run [s] (0 = none): reached, the run stops as "interrupted".
inline constexpr Key<double> max_wall{"run.max_wall"};
// Engine work this invocation may do (ED: events, DEM: steps; 0 = no limit): reached, the
// run stops as "interrupted" with a checkpoint, like max_wall, but at a reproducible point.
inline constexpr Key<std::int64_t> max_steps{"run.max_steps"};
// Simulated time between checkpoints (0 = only when interrupted or at max_wall).
inline constexpr Key<double> checkpoint_every{"output.checkpoint_every"};
// How long the MP4 of a run should last when the scene gives no output.fps [s].
inline constexpr Key<double> video_seconds{"output.video_seconds"};
// Declares run.max_wall, run.max_steps, output.checkpoint_every and the bounds on frames
// and stats rows a scene may ask for.
void declare(Schema& s);
}  // namespace loop_keys

struct RunOptions {
  std::filesystem::path dir;  // the run folder
  bool force = false;         // replace a previous run's results in `dir`
  // Continue the run in `dir` from its newest checkpoint (the scene is DIR/scene.toml,
  // with --set overrides of keys marked may_change_on_resume only).
  bool resume = false;
  std::string name;           // the MP4's name: DIR/<name>.mp4 (the scene file's stem)
  bool quiet = false;         // no summary line on stdout
};

// Runs a validated scene. Returns the process status: 0 complete, 130 interrupted; throws
// grainflow::Error when the run fails (run.json then says "failed").
int run_scene(const Scene& scene, const RunOptions& options);

// The caption line under the panels: title, time, N, exposure, stream velocity, then the
// engine's labels (the phase in effect, Re and Ma of [medium]).
std::string frame_caption(const std::string& title, double exposure, const render::Snapshot& s);

// The `--set output.fps=N` that makes a fresh run's video last about output.video_seconds
// (N = frames / video_seconds, 1..60), or nothing when the scene gives output.fps itself or
// counts its run in run.steps (frames unknown). `grainflow run` applies it before the
// effective scene is written, so a resume keeps the rate the video started with.
std::optional<std::string> auto_fps_override(const Scene& scene);

}  // namespace grainflow::scenes
