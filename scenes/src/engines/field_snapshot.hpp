// Binned fields (engine/core/binning) → the named fields a Snapshot carries for the
// field panels and the field files. The one mapping of field names used by `render` and
// `run`: "density", "temperature" (kT), "speed" (<|v|>), "vorticity" (ω_z of the mean velocity), "fraction", "samples"
// (particle-samples per bin), "open_fraction" (the part of each bin open to particle
// centres: 1 unless the runner says otherwise, as the ED runner does around its
// obstacle), and the mean velocity.
#pragma once
#include <optional>
#include <string>

#include "engine/core/binning.hpp"
#include "render/snapshot.hpp"

namespace grainflow::scenes {

// The units the colour bars name ("n [σ⁻²]"); empty: none shown (reduced units, or a
// particle file whose units are unknown).
struct FieldUnits {
  std::string density;      // number per unit bin area (3D: projected on the plane)
  std::string temperature;  // kT, an energy
  std::string speed;
  std::string rate;         // vorticity, 1/time
  // What the temperature map's bar calls it: kT in the ED engine's units; in the DEM
  // engine m<C²>/3 (J), a velocity variance weighted by the sphere mass, not a thermal kT.
  std::string temperature_label = "kT";
};

void set_binned_fields(core::BinnedFields fields, render::Snapshot& s, const FieldUnits& units = {},
                       std::optional<render::FieldExposure> exposure = std::nullopt);

}  // namespace grainflow::scenes
