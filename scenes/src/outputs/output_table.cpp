#include "scenes/src/outputs/output_table.hpp"

#include <array>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

// Each output's row, defined in its own file in this folder.
OutputEntry png_output();
OutputEntry mp4_output();
OutputEntry particles_output();
OutputEntry lammps_dump_output();
OutputEntry stats_output();
OutputEntry fields_output();
OutputEntry run_json_output();

std::span<const OutputEntry> outputs() {
  // run.json last: it is finished once every other file is in place, and records that.
  static const std::array<OutputEntry, 7> table = {png_output(),   mp4_output(),    particles_output(),
                                                   lammps_dump_output(), stats_output(), fields_output(),
                                                   run_json_output()};
  return table;
}

void declare_output_keys(Schema& s) {
  s.section("output", "what the run writes into its folder");
  for (const auto& o : outputs()) o.declare_keys(s);
}

}  // namespace grainflow::scenes
