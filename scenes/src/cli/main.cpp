// grainflow: granular matter simulations rendered headlessly. Dispatches to subcommands.
#include <cstdio>
#include <cstdlib>
#include <exception>

#include <unistd.h>

#include "engine/core/error.hpp"
#include "scenes/src/cli/commands.hpp"

namespace {

// OpenMP threads that spin while they wait (libgomp's default) make the DEM engine 20–50×
// slower with 2 threads whenever another process holds a core: every barrier waits a
// scheduler time slice (measured: 1.2e6 vs 6.1e7 particle-steps/s, N = 2,000, load 4 on 2
// cores). Sleeping waits cost a few per cent on an idle machine, so they are our default.
// libgomp reads its environment when it is loaded, before main(), so the process restarts
// itself once with OMP_WAIT_POLICY=passive. A user who sets OMP_WAIT_POLICY keeps it.
void default_to_passive_omp_wait(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 0) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: then run on with the default
}

}  // namespace

int main(int argc, char** argv) {
  default_to_passive_omp_wait(argv);
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
  setup_plot_command(app, status);
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
