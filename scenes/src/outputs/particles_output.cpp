// DIR/particles.xyz (output.particles): every frame's particles as extended XYZ that OVITO
// and ASE read as they are — persistent ids, groups (type), positions, radii, velocities,
// spins (omega) and masses, box, periodic axes and time — at float64 (exact: the file
// reads back bit for bit, and a run can start from it, system.initial.file) or float32
// (output.particles_precision). The precision key, shared with particles.lammpstrj, is
// declared here.
#include "engine/io/xyz_writer.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/particle_file_output.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {

io::Precision particle_precision(const Scene& scene) {
  return scene.get(particles_precision) == "float32" ? io::Precision::float32 : io::Precision::float64;
}

namespace {

constexpr Key<bool> particles{"output.particles"};

void declare(Schema& s) {
  auto& t = s.table("output");
  t.add_bool(particles, false,
             "write every frame's particles (persistent ids, groups as type, positions, radii, velocities, spins, "
             "masses) to particles.xyz, extended XYZ that OVITO and ASE read");
  t.add_enum(particles_precision, {"float64", "float32"}, "float64",
             "real numbers in particles.xyz and particles.lammpstrj: float64 (exact, reads back bit for bit) or "
             "float32 (7 significant digits, about 2/3 of the size)");
}

std::unique_ptr<RunOutput> open(const OutputContext& c) {
  if (!c.scene.get(particles)) return nullptr;
  c.claim("particles.xyz");
  return std::make_unique<ParticleFileOutput<io::XyzWriter>>(c.dir / "particles.xyz", particle_precision(c.scene));
}

}  // namespace

OutputEntry particles_output() {
  return {"particles", "particles.xyz, extended XYZ of every frame", &declare, nullptr, &open};
}

}  // namespace grainflow::scenes
