// The one registration place for engines: the name a scene gives in run.engine, a line
// for `grainflow info`, the engine's [system]/[boundary] schema and its run adapter.
// Adding an engine means adding one entry to engines() in engines.cpp.
#pragma once
#include <memory>
#include <string_view>
#include <vector>

namespace grainflow::scenes {

class Schema;
class Scene;
class EngineRunner;

struct EngineEntry {
  std::string_view name;
  std::string_view description;
  void (*add_schema)(Schema&);
  std::unique_ptr<EngineRunner> (*make_runner)(const Scene&);
};

const std::vector<EngineEntry>& engines();

}  // namespace grainflow::scenes
