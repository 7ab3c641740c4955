#include "scenes/src/engines/sampling.hpp"

namespace grainflow::scenes::sample_keys {

void declare(Schema& s) {
  auto& sample = s.section("sample", "binned measurement fields (seed 003 §4.1)");
  sample.add_float(exposure, 1.0, "exposure τ_E: time over which binned fields are averaged per frame", "time units")
      .above(0.0);
  sample.add_int_array(bins, {60, 60}, {"nx", "ny"}, "number of bins of the measurement grid").at_least(1).at_most(4096);
}

}  // namespace grainflow::scenes::sample_keys
