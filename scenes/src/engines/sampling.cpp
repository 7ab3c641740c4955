#include "scenes/src/engines/sampling.hpp"

namespace grainflow::scenes::sample_keys {

void declare(Schema& s) {
  auto& sample = s.section("sample", "binned measurement fields (seed 003 §4.1)");
  sample.add_float(exposure, 1.0, "exposure τ_E: time over which binned fields are averaged per frame", "time units")
      .above(0.0);
  sample.add_int_array(bins, {kDefaultBins[0], kDefaultBins[1]}, {"nx", "ny"},
                       "number of bins of the measurement grid; absent: 60 × 60 in 2D (ED), and in 3D (DEM) bins "
                       "about two of the largest diameters wide (4 r_max or wider: a sphere is binned by its centre, "
                       "so bins narrower than ~2 diameters stripe with its layers; finer bins may still be asked "
                       "for, e.g. for a profile across a sheared gap)")
      .at_least(1)
      .at_most(4096)
      .optional();
}

}  // namespace grainflow::scenes::sample_keys
