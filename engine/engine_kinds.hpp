// The engines this build provides, by the name a scene file uses in [run] engine = "…".
#pragma once
#include <string_view>
#include <vector>

namespace grainflow {

struct EngineKind {
  std::string_view name;         // scene-file name
  std::string_view description;  // one line for `grainflow info` and error messages
};

const std::vector<EngineKind>& engine_kinds();

}  // namespace grainflow
