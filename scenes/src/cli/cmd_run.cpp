// `grainflow run SCENE.toml -o DIR [--set key=value …] [--force] [--threads N]`: validates
// the scene, then hands it to the run loop (run/run_loop.hpp), which writes DIR/scene.toml,
// frames/*.png, <name>.mp4, stats.csv, particles.xyz (optional) and run.json.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/dem/simulation.hpp"
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
  int threads = 0;  // 0: as OMP_NUM_THREADS says, else all cores
};

int run_command(const RunArgs& a) {
  const Scene scene = load_scene(a.scene, a.overrides);
  // The DEM engine's OpenMP team; its results do not depend on the count.
  if (a.threads > 0) dem::set_thread_count(a.threads);
  RunOptions opt;
  opt.dir = a.out_dir;
  opt.force = a.force;
  opt.name = std::filesystem::path(a.scene).stem().string();
  return run_scene(scene, opt);
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
  cmd->callback([args, &status] { status = run_command(*args); });
}

}  // namespace grainflow::scenes
