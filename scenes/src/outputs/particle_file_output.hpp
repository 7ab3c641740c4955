// What the particle-file outputs (particles.xyz, particles.lammpstrj) share: the precision
// key both read, and the RunOutput that writes every frame's particles through an
// io::ParticleFileWriter (a PartialFile a resumed run continues from its checkpoint).
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "engine/io/archive.hpp"
#include "engine/io/particle_file_writer.hpp"
#include "scenes/src/outputs/run_output.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

// "float64" (the default: exact, for checks and restarts) or "float32" (≈ 2/3 the bytes).
// Declared by the particles.xyz output (particles_output.cpp), read by every particle file.
inline constexpr Key<std::string> particles_precision{"output.particles_precision"};
io::Precision particle_precision(const Scene& scene);

template <class Writer>
class ParticleFileOutput final : public RunOutput {
public:
  ParticleFileOutput(std::filesystem::path file, io::Precision precision)
      : file_(std::move(file)), precision_(precision) {}
  void start(const RunRecord&) override { writer_.emplace(file_.string(), precision_); }
  void checkpoint(io::ArchiveWriter& w) override {
    w.tag(file_.filename().string());
    w.pod(writer_->flush());
    w.pod(writer_->frames());
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag(file_.filename().string());
    const auto size = r.get<std::uint64_t>();
    const int frames = r.get<int>();
    writer_.emplace(file_.string(), size, frames, precision_);
  }
  bool wants_particles() const override { return true; }
  // The frame's number in the run is the step of a frame that has none (LAMMPS TIMESTEP
  // of the ED engine).
  void particles(std::int64_t index, const core::ParticleFrame& f) override { writer_->write(f, index); }
  void finish(const RunRecord&) override { writer_->close(); }

private:
  std::filesystem::path file_;
  io::Precision precision_;
  std::optional<Writer> writer_;
};

}  // namespace grainflow::scenes
