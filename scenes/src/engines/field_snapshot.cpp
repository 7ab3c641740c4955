#include "scenes/src/engines/field_snapshot.hpp"

#include <utility>

namespace grainflow::scenes {

namespace {
std::string with_unit(std::string label, const std::string& unit) {
  return unit.empty() ? label : label + " [" + unit + "]";
}
}  // namespace

void set_binned_fields(core::BinnedFields f, render::Snapshot& s, const FieldUnits& units,
                       std::optional<render::FieldExposure> exposure) {
  s.fields.clear();
  const core::GridGeometry grid = f.density.grid;
  s.fields.push_back({"density", with_unit("n", units.density), std::move(f.density)});
  if (f.fraction) s.fields.push_back({"fraction", s.dim == 3 ? "solid fraction" : "area fraction", std::move(*f.fraction)});
  if (f.temperature) s.fields.push_back({"temperature", with_unit(units.temperature_label, units.temperature), std::move(*f.temperature)});
  if (f.mean_speed) s.fields.push_back({"speed", with_unit("<|v|>", units.speed), std::move(*f.mean_speed)});
  if (f.counts.size() == grid.size()) {
    core::ScalarField samples(grid, 0.0);
    for (std::size_t b = 0; b < f.counts.size(); ++b) samples.values[b] = double(f.counts[b]);
    s.fields.push_back({"samples", "particle-samples", std::move(samples)});
  }
  s.fields.push_back({"open_fraction", "open fraction", core::ScalarField(grid, 1.0)});
  if (f.mean_velocity) s.fields.push_back({"vorticity", with_unit("ω", units.rate), core::vorticity(*f.mean_velocity)});
  if (f.mean_velocity) s.velocity = std::move(*f.mean_velocity);
  else s.velocity.reset();
  s.exposure = exposure;
}

}  // namespace grainflow::scenes
