// DIR/particles.xyz (output.particles): every frame's particles as extended XYZ with box,
// periodic axes, ids, groups (type), radii, velocities, spins and masses at full precision
// (shortest round-trip text), for OVITO and ParaView, and to start a run from
// (system.initial.file).
#include <optional>

#include "engine/io/archive.hpp"
#include "engine/io/xyz_writer.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

constexpr Key<bool> particles{"output.particles"};

class ParticlesOutput final : public RunOutput {
public:
  explicit ParticlesOutput(std::filesystem::path file) : file_(std::move(file)) {}
  void start(const RunRecord&) override { writer_.emplace(file_.string()); }
  void checkpoint(io::ArchiveWriter& w) override {
    w.tag("particles.xyz");
    w.pod(writer_->flush());
    w.pod(writer_->frames());
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag("particles.xyz");
    const auto size = r.get<std::uint64_t>();
    writer_.emplace(file_.string(), size, r.get<int>());
  }
  bool wants_particles() const override { return true; }
  void particles(std::int64_t, const core::ParticleFrame& f) override { writer_->write(f); }
  void finish(const RunRecord&) override { writer_->close(); }

private:
  std::filesystem::path file_;
  std::optional<io::XyzWriter> writer_;
};

void declare(Schema& s) {
  s.table("output").add_bool(particles, false, "write every frame's particles (ids, positions, radii, velocities, spins) to particles.xyz (OVITO-readable)");
}

std::unique_ptr<RunOutput> open(const OutputContext& c) {
  if (!c.scene.get(particles)) return nullptr;
  c.claim("particles.xyz");
  return std::make_unique<ParticlesOutput>(c.dir / "particles.xyz");
}

}  // namespace

OutputEntry particles_output() {
  return {"particles", "particles.xyz, extended XYZ of every frame", &declare, nullptr, &open};
}

}  // namespace grainflow::scenes
