// What the run loop (`grainflow run`) needs from an engine, whatever its physics: advance
// in simulated time, draw its state into a Snapshot, give a stats.csv row and its
// throughput. One adapter per engine (ed/ed_runner.cpp, dem/dem_runner.cpp), registered in
// the engine table (engine_table.cpp).
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/core/particle_frame.hpp"
#include "render/snapshot.hpp"
#include "scenes/src/outputs/run_output.hpp"

namespace grainflow::scenes {

class EngineRunner {
public:
  virtual ~EngineRunner() = default;

  virtual double time() const = 0;
  // Runs toward simulated time t (events/steps up to t; the clock ends at t or at the
  // last step not past it), but returns earlier after a bounded amount of work (a fraction
  // of a second), so that the run loop answers Ctrl-C and SIGTERM even when the clock
  // barely moves (a collapsing inelastic system); time() says how far it got.
  virtual void advance_to(double t) = 0;
  // Runs `n` units of the engine's own work count (ED: events, DEM: steps).
  virtual void advance_steps(std::uint64_t n) = 0;
  virtual std::uint64_t steps_done() const = 0;

  // Particles (synchronised to time()), domain and obstacles, coloured by `colour_by`
  // (render.color_by: one of the engine's colour attributes, checked by validation).
  virtual void snapshot(const std::string& colour_by, render::Snapshot& out) = 0;

  // The exact state of the particles at time() (after snapshot(), which synchronises
  // them): ids that stay with a particle while it is in the system, type = group + 1,
  // positions, radii, velocities, and the columns omega (2D; 3D: omegax, omegay, omegaz)
  // and mass. For particles.xyz, and what system.initial.file reads back.
  virtual void particles(core::ParticleFrame& out) const = 0;

  // stats.csv: column names (after `time`) and one row over the window since the last
  // row; taking a row starts a new window. Throws like check_finite() when the values it
  // has just computed are no longer finite.
  virtual std::vector<StatsColumn> stats_columns() const = 0;
  virtual std::vector<double> stats_row() = 0;
  // Throws grainflow::Error naming the quantity when the state has turned non-finite (a
  // run would otherwise end "complete" with NaN everywhere). Called at the end of the run;
  // stats_row() checks every row with the values it computes anyway.
  virtual void check_finite() const {}

  // Throughput: total work so far and its unit ("collisions", "particle-steps").
  virtual double work() const = 0;
  virtual std::string work_unit() const = 0;
  // Totals for run.json.
  virtual std::vector<std::pair<std::string, double>> figures() const = 0;
  // Fingerprint of the exact state (core::StateDigest, hex) for run.json: equal digests
  // mean bit-identical runs. Empty when the engine has none.
  virtual std::string state_digest() const { return {}; }
  // Advice on how the run went, printed after the closing line (e.g. a setting that cost
  // more than it gained). Empty: nothing to say.
  virtual std::string advice() const { return {}; }

  // Checkpoints (output.checkpoint_every, SIGINT/SIGTERM, run.max_wall): every mutable
  // bit of the engine's state, the measurement windows of stats rows and frames included.
  // load() restores it into a runner built from the same scene, which then continues bit
  // for bit; it throws grainflow::Error when the saved state does not fit.
  virtual void save(io::ArchiveWriter& w) const = 0;
  virtual void load(io::ArchiveReader& r) = 0;

  // Engine-specific files in the run folder (DEM: pair.csv), opened once before the first
  // step; the run loop finishes or fails them with the table's outputs.
  virtual std::vector<std::unique_ptr<RunOutput>> open_outputs(const OutputContext& /*context*/) { return {}; }
};

}  // namespace grainflow::scenes
