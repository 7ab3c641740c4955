// `grainflow run SCENE.toml -o DIR [--set key=value …] [--force] [--threads N]`: validates
// the scene, then hands it to the run loop (run/run_loop.hpp), which writes DIR/scene.toml,
// frames/*.png, <name>.mp4, stats.csv, particles.xyz (optional) and run.json.
// `grainflow run --resume DIR [--set run.until=…]` continues the run in DIR from its newest
// checkpoint, with DIR/scene.toml.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <regex>

#include "engine/core/error.hpp"
#include "engine/dem/simulation.hpp"
#include "engine/ed/simulation.hpp"
#include "scenes/src/scene/overrides.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/cli/commands.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/run/scene_catalog.hpp"

namespace grainflow::scenes {
namespace {

struct RunArgs {
  std::string scene;
  std::string out_dir;
  std::vector<std::string> overrides;
  bool force = false;
  std::string resume;  // run folder to continue
  int threads = 0;     // 0: as OMP_NUM_THREADS says, else all cores
};

// On --resume only keys that decide nothing the checkpoint holds may change.
void check_resume_overrides(const std::vector<std::string>& overrides, const Scene& scene) {
  const Schema& schema = schema_for_engine(scene.engine());
  std::string allowed;
  for (const auto& table : schema.tables())
    for (const auto& k : table.keys())
      if (k.resumable) allowed += (allowed.empty() ? "" : ", ") + table.path() + "." + k.name;
  for (const auto& text : overrides) {
    const Override o = parse_override(text);
    // Array elements ("system.group[1].radius") are looked up by their key.
    const std::string path = std::regex_replace(o.key, std::regex(R"(\[[0-9]+\])"), "");
    const KeySpec* k = schema.find_key(path);
    if (!k || !k->resumable)
      throw Error("--set " + o.key + " cannot change on --resume: the checkpoint holds a state made with the scene's "
                  "value; allowed on --resume: " + allowed + " (to change anything else, start a new run)");
  }
}

int run_command(const RunArgs& a) {
  // The DEM engine's OpenMP team; its results do not depend on the count.
  // The DEM engine's OpenMP team and the ED engine's lanes (system.lanes = 2); the results
  // depend on neither.
  if (a.threads > 0) {
    dem::set_thread_count(a.threads);
    ed::set_lane_threads(a.threads);
  }
  RunOptions opt;
  if (!a.resume.empty()) {
    if (!a.scene.empty() || !a.out_dir.empty() || a.force)
      throw Error("--resume DIR continues the run in DIR with DIR/scene.toml: give no scene file, -o or --force");
    const std::filesystem::path dir = a.resume;
    const std::filesystem::path scene_file = dir / "scene.toml";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(scene_file, ec))
      throw Error("cannot resume in '" + dir.string() + "': it holds no scene.toml (not a grainflow run folder?)");
    const Scene scene = load_scene(scene_file, a.overrides);
    check_resume_overrides(a.overrides, scene);
    opt.dir = dir;
    opt.resume = true;
    return run_scene(scene, opt);
  }
  if (a.scene.empty() || a.out_dir.empty()) throw Error("run needs a scene file and -o DIR (or --resume DIR)");
  // A scene without output.fps gets a rate that makes its video last output.video_seconds,
  // written into the effective scene like any --set.
  std::vector<std::string> overrides = a.overrides;
  if (auto fps = auto_fps_override(load_scene(a.scene, overrides))) overrides.push_back(*fps);
  const Scene scene = load_scene(a.scene, overrides);
  opt.dir = a.out_dir;
  opt.force = a.force;
  opt.name = std::filesystem::path(a.scene).stem().string();
  return run_scene(scene, opt);
}

}  // namespace

void setup_run_command(CLI::App& app, int& status) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run a scene file: simulate, draw every exposure, write the run folder");
  cmd->add_option("scene", args->scene, "Scene file (TOML), e.g. scenes/disks_box.toml")->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->out_dir, "Run folder to create");
  cmd->add_option("--resume", args->resume,
                  "Continue the run in this folder from its newest checkpoint (--set: only run.until, run.steps, "
                  "run.max_wall, output.checkpoint_every)");
  cmd->add_option("--set", args->overrides, "Override a scene key: section.key=value (repeatable)")
      ->allow_extra_args(false);
  cmd->add_flag("--force", args->force, "Replace the results of a previous run in the folder");
  cmd->add_option("--threads", args->threads,
                  "Threads of the DEM engine (default: OMP_NUM_THREADS, else all cores) and of the ED engine's two lanes "
                  "(system.lanes = 2; default: 2 where there are two cores); results do not depend on it")
      ->check(CLI::PositiveNumber);
  cmd->callback([args, &status] { status = run_command(*args); });
}

}  // namespace grainflow::scenes
