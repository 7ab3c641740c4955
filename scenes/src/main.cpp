// grainflow: granular matter simulations rendered headlessly. Dispatches to subcommands.
#include <cstdio>
#include <exception>

#include "engine/core/error.hpp"
#include "scenes/src/commands.hpp"

int main(int argc, char** argv) {
  using namespace grainflow::scenes;
  CLI::App app{"grainflow: granular matter simulations (DEM and event-driven) rendered headlessly"};
  app.set_version_flag("--version", GRAINFLOW_VERSION_STRING);
  app.require_subcommand(1);
  int status = 0;
  // The one registration place for subcommands.
  setup_run_command(app, status);
  setup_info_command(app, status);
  setup_render_command(app, status);
  setup_diff_command(app, status);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const grainflow::Error& e) {
    std::fprintf(stderr, "grainflow: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grainflow: internal error: %s\n", e.what());
    return 3;
  }
  return status;
}
