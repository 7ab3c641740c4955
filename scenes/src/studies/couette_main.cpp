// couette_study: runs a planar Couette scene (scenes/studies/couette.toml) and prints the
// kinematic viscosity from the wall shear stress and the bulk velocity gradient
// (studies/couette.hpp). Usage:
//   couette_study SCENE.toml [--skip T] [--bulk F] [--set key=value ...] [-o REPORT.txt]
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene_error.hpp"
#include "scenes/src/studies/couette.hpp"

int main(int argc, char** argv) {
  CLI::App app{"planar Couette flow → kinematic viscosity (seed 003 §4.2)"};
  std::string scene_path, report;
  std::vector<std::string> sets;
  grainflow::scenes::studies::CouetteRun run;
  run.skip = 3000.0;
  app.add_option("scene", scene_path, "Couette scene (walls in y, periodic x)")->required();
  app.add_option("--skip", run.skip, "simulated time before the first block (the profile develops)");
  app.add_option("--bulk", run.bulk_fraction, "middle fraction of the channel taken as the bulk");
  app.add_option("--set", sets, "section.key=value overrides, as for grainflow run");
  app.add_option("-o,--output", report, "also write the report to this file");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto scene = grainflow::scenes::load_scene(scene_path, sets);
    const auto in = grainflow::scenes::studies::measure_couette(scene, run);
    const auto result = grainflow::scenes::studies::analyse_couette(in);
    const std::string text = grainflow::scenes::studies::couette_report(in, result);
    std::fputs(text.c_str(), stdout);
    if (!report.empty()) grainflow::io::write_text_atomically(report, text);
  } catch (const grainflow::scenes::SceneError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const grainflow::Error& e) {
    std::fprintf(stderr, "couette_study: %s\n", e.what());
    return 1;
  }
  return 0;
}
