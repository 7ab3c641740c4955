#include "scenes/src/engines/engine_table.hpp"

#include <array>

namespace grainflow::scenes {

// Each engine's row, defined beside its keys and runner in engines/<name>/.
EngineEntry ed_engine();
EngineEntry dem_engine();

std::span<const EngineEntry> engines() {
  static const std::array<EngineEntry, 2> table = {ed_engine(), dem_engine()};
  return table;
}

const EngineEntry* find_engine(std::string_view name) {
  for (const auto& e : engines())
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> engine_names() {
  std::vector<std::string> names;
  for (const auto& e : engines()) names.emplace_back(e.name);
  return names;
}

}  // namespace grainflow::scenes
