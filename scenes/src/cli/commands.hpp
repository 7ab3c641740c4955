// The CLI subcommands of `grainflow`. Each adds its CLI11 subcommand to the app and, when
// chosen, runs and stores its process exit status in `status`:
//   0 success, 1 a negative answer (e.g. `diff`: images differ), 2 an error.
// Errors are thrown as grainflow::Error and printed by main().
#pragma once
#include <CLI/CLI.hpp>

namespace grainflow::scenes {

void setup_run_command(CLI::App& app, int& status);
void setup_info_command(CLI::App& app, int& status);
void setup_render_command(CLI::App& app, int& status);
void setup_diff_command(CLI::App& app, int& status);
void setup_plot_command(CLI::App& app, int& status);

}  // namespace grainflow::scenes
