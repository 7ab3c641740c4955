// Binned fields (engine/core/binning) → the named fields a Snapshot carries for the
// field panels. The one mapping of field names used by `render` and `run`: "density",
// "temperature" (kT), "speed" (<|v|>), "fraction", and the mean velocity.
#pragma once
#include "engine/core/binning.hpp"
#include "render/snapshot.hpp"

namespace grainflow::scenes {

void set_binned_fields(core::BinnedFields fields, render::Snapshot& s);

}  // namespace grainflow::scenes
