// The measurement agent of seed 003 §4.1: a TimerAgent that every `interval` deposits all
// disks (at the current time) into a core::BinAccumulator and, every exposure τ_E, turns
// the sums into time-averaged binned fields (density, mean velocity, kT (Eq. 4.9, i = 2),
// mean speed, area fraction).
#pragma once
#include <vector>

#include "engine/core/binning.hpp"
#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

struct SamplerConfig {
  core::GridGeometry grid;  // usually the box, e.g. 60 × 60 bins
  double interval = 1.0;    // time between samples
  double exposure = 60.0;   // τ_E: a multiple of interval (rounded to the nearest one)
};

// One exposure's averaged fields.
struct ExposureFields {
  double t_begin = 0.0, t_end = 0.0;
  int samples = 0;
  core::BinnedFields fields;
};

class FieldSampler final : public TimerAgent {
public:
  // Throws grainflow::Error when interval or exposure are not positive.
  FieldSampler(const SamplerConfig& cfg, double t_start);
  std::string_view name() const override { return "sampler"; }
  double event_time(const SystemState& state) const override;
  void action(SystemState& state) override;
  // The sample clock, the partial exposure's sums and the completed frames not yet taken.
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  // Completed exposures, oldest first; take_frames() hands them over and clears the list.
  const std::vector<ExposureFields>& frames() const { return frames_; }
  std::vector<ExposureFields> take_frames();
  // When the exposure in progress ends (its frame comes out then).
  double exposure_end() const { return t_begin_ + cfg_.exposure; }

private:
  SamplerConfig cfg_;
  core::BinAccumulator acc_;
  int per_exposure_;
  long long k_ = 0;  // samples taken
  double t_start_, t_begin_;
  std::vector<ExposureFields> frames_;
};

}  // namespace grainflow::ed
