// `grainflow info`: what this build can do here — engines, GL backends with their GL
// version and renderer strings, and the library versions it runs with.
#include <cstdio>

#include "engine/engine_kinds.hpp"
#include "scenes/src/commands.hpp"

namespace grainflow::scenes {

void setup_info_command(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("info", "Print engines, GL backends and library versions");
  cmd->callback([&status] {
    std::printf("grainflow %s\n", GRAINFLOW_VERSION);
    std::printf("engines:\n");
    for (const auto& k : engine_kinds())
      std::printf("  %-4.*s %.*s\n", int(k.name.size()), k.name.data(), int(k.description.size()),
                  k.description.data());
    status = 0;
  });
}

}  // namespace grainflow::scenes
