// The [sample] keys every engine consumes (seed 003 §4.1): the exposure τ_E over which the
// binned fields of a frame are time-averaged and the bins of the measurement grid, and the
// one rule for how often an exposure samples the state, the same for both engines.
#pragma once
#include <array>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes::sample_keys {

inline constexpr Key<double> exposure{"sample.exposure"};
inline constexpr Key<std::array<int, 2>> bins{"sample.bins"};
// The bins of a 2D (ED) grid when sample.bins is absent; the DEM engine sizes its own from
// the particle diameter.
inline constexpr std::array<int, 2> kDefaultBins{60, 60};

// Declares [sample] with the keys above.
void declare(Schema& s);

// An exposure averages this many samples of the state, evenly spaced (ED: a timer agent
// every τ_E/40; DEM: every τ_E/40 of simulated time, at the nearest whole step).
inline constexpr int kSamplesPerExposure = 40;
inline double sample_interval(double exposure) { return exposure / kSamplesPerExposure; }

}  // namespace grainflow::scenes::sample_keys
