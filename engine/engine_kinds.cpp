#include "engine/engine_kinds.hpp"

namespace grainflow {

const std::vector<EngineKind>& engine_kinds() {
  static const std::vector<EngineKind> kinds = {
      {"ed", "2D event-driven hard disks (seed 003, Baryshev 2003)"},
      {"dem", "3D soft-sphere DEM with Walton contacts (seed 000, Sweetman 2003)"},
  };
  return kinds;
}

}  // namespace grainflow
