// The one table of engines: the name a scene gives in run.engine, a line for `grainflow
// info`, the keys the engine consumes ([system], [boundary], and any others its runner
// reads), the colour attributes its particles offer to render.color_by, and its runner.
// Adding an engine = a folder engines/<name>/ (keys + runner) and one row in
// engine_table.cpp.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace grainflow::scenes {

class Schema;
class Scene;
class EngineRunner;

struct EngineEntry {
  std::string_view name;
  std::string_view description;
  void (*declare_keys)(Schema&);
  // The values render.color_by may take for this engine's particles ("uniform" first).
  std::vector<std::string> (*colour_attributes)();
  std::unique_ptr<EngineRunner> (*make_runner)(const Scene&);
};

std::span<const EngineEntry> engines();
// The row of `name`, or nullptr.
const EngineEntry* find_engine(std::string_view name);
std::vector<std::string> engine_names();

}  // namespace grainflow::scenes
