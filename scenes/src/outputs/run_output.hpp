// The extension point for what a run writes into its folder (besides the pictures, which
// go through render's FrameSinks): an output receives each frame's Snapshot, each stats
// row and the run's record at its start and end. Outputs know no engine: they see only
// Snapshots, rows and records. Registered in the one output table (output_table.cpp).
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/particle_frame.hpp"
#include "render/snapshot.hpp"

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::scenes {

class Scene;
struct RunRecord;

// The claim of the frame sequence: every frames/frame_NNNNNN.png (6 or more digits, as
// render::PngSequenceSink names them).
inline constexpr std::string_view kFrameFiles = "frames/frame_*.png";

// A stats.csv column as the code that computes it names and documents it (stats.json): its
// unit and what it is, written beside the value, one place per column. ED units: σ (disk
// diameter), m (disk mass), E (the energy unit of system.kT), τ = σ·sqrt(m/E); DEM: SI.
struct StatsColumn {
  std::string name;
  std::string unit;        // "1" for counts and ratios
  std::string definition;  // what the value is, over which window, and how it is computed
};

// What an output is opened with.
struct OutputContext {
  const Scene& scene;
  std::filesystem::path dir;                // the run folder
  std::string name;                         // the scene file's stem: DIR/<name>.mp4
  std::vector<StatsColumn> stats_columns;   // after `time`, as the engine names them
  // Every file an output writes in DIR is claimed first (relative name, or kFrameFiles),
  // so that --force later removes exactly what grainflow wrote (run/run_folder.hpp).
  std::function<void(std::string_view)> claim;
  // Set when the run continues from a checkpoint (`grainflow run --resume`): the frames
  // written before it. Outputs then get resume() instead of start().
  std::optional<std::int64_t> resume_frames;
};

// Files are created in start() (or resume()), not when the output is opened: opening
// only claims them, so a resume that fails leaves the folder as it was.
class RunOutput {
public:
  virtual ~RunOutput() = default;
  // Before the first step (run.json: status "running").
  virtual void start(const RunRecord& /*record*/) {}
  // A checkpoint is being taken: flush what was written and save what resume() needs to
  // continue from exactly here (file sizes, rows). Every output must decide what that is.
  virtual void checkpoint(io::ArchiveWriter& w) = 0;
  // Instead of start(), when the run continues from a checkpoint: read back what
  // checkpoint() saved and continue the files from there (what was written after the
  // checkpoint is cut off and written again).
  virtual void resume(io::ArchiveReader& r, const RunRecord& record) = 0;
  // Every frame, in time order: particles and fields as drawn.
  virtual void frame(std::int64_t /*index*/, const render::Snapshot& /*snapshot*/) {}
  // Outputs of the particles themselves want their exact state every frame (float64
  // positions and velocities, spins, masses, ids, groups), which the run loop asks the
  // engine for only when some output wants it (EngineRunner::particles).
  virtual bool wants_particles() const { return false; }
  virtual void particles(std::int64_t /*index*/, const core::ParticleFrame& /*frame*/) {}
  // Every stats row, in time order.
  virtual void stats(double /*time*/, std::span<const double> /*row*/) {}
  // Every few seconds of a running run, with its figures so far (run.json refreshes, so
  // that a killed run's record says how far it got).
  virtual void progress(const RunRecord& /*record*/) {}
  // The run ended, complete or interrupted: every file is put in place under its name.
  virtual void finish(const RunRecord& record) = 0;
  // The run failed: nothing finished-looking is left behind (run.json says "failed").
  virtual void fail(const RunRecord& /*record*/) {}
};

}  // namespace grainflow::scenes
