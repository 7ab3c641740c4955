#include "scenes/src/engines/field_snapshot.hpp"

#include <utility>

namespace grainflow::scenes {

void set_binned_fields(core::BinnedFields f, render::Snapshot& s) {
  s.fields.clear();
  s.fields.push_back({"density", "n", std::move(f.density)});
  if (f.fraction) s.fields.push_back({"fraction", "area/solid fraction", std::move(*f.fraction)});
  if (f.temperature) s.fields.push_back({"temperature", "kT", std::move(*f.temperature)});
  if (f.mean_speed) s.fields.push_back({"speed", "<|v|>", std::move(*f.mean_speed)});
  if (f.mean_velocity) s.velocity = std::move(*f.mean_velocity);
  else s.velocity.reset();
}

}  // namespace grainflow::scenes
