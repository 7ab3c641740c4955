// DIR/particles.xyz (output.particles): every frame's particles as extended XYZ with box,
// periodic axes, radii and the colour attribute, for OVITO and ParaView.
#include <optional>

#include "engine/io/archive.hpp"
#include "engine/io/xyz_writer.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

constexpr Key<bool> particles{"output.particles"};

// Particle file frame from a snapshot, so OVITO/ParaView get positions and radii.
void to_particle_frame(const render::Snapshot& s, core::ParticleFrame& f) {
  f.clear();
  f.dim = s.dim;
  f.time = s.time;
  f.has_box = true;
  f.box_lo = s.lo;
  f.box_hi = s.hi;
  f.periodic = s.periodic;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float* p = &s.pos_radius[4 * i];
    f.id.push_back(std::int64_t(i + 1));
    f.position.emplace_back(p[0], p[1], p[2]);
    f.radius.push_back(p[3]);
    f.type.push_back(1);
  }
  if (!s.attribute.empty())
    f.extra.emplace_back(s.attribute_name, std::vector<double>(s.attribute.begin(), s.attribute.end()));
}

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
  void frame(std::int64_t, const render::Snapshot& s) override {
    to_particle_frame(s, frame_);
    writer_->write(frame_);
  }
  void finish(const RunRecord&) override { writer_->close(); }

private:
  std::filesystem::path file_;
  std::optional<io::XyzWriter> writer_;
  core::ParticleFrame frame_;
};

void declare(Schema& s) {
  s.table("output").add_bool(particles, false, "write particle positions and radii of every frame (OVITO-readable)");
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
