#include "scenes/src/engines/engine_table.hpp"

#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

const std::vector<EngineEntry>& engines() {
  static const std::vector<EngineEntry> list = {
      {"ed", "2D event-driven hard disks (seed 003, Baryshev 2003)", &add_ed_schema, &make_ed_runner},
      {"dem", "3D soft-sphere DEM with Walton contacts (seed 000, Sweetman 2003)", &add_dem_schema,
       &make_dem_runner},
  };
  return list;
}

}  // namespace grainflow::scenes
