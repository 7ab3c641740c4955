// DIR/particles.lammpstrj (output.lammps_dump): every frame's particles as a LAMMPS text
// dump (`ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz mass`) that LAMMPS
// read_dump/rerun, OVITO and `grainflow render` read. TIMESTEP is the DEM engine's step,
// and for the ED engine, which has no steps, the frame's number (0, 1, … one per
// exposure); ITEM: TIME holds the simulated time in both. Precision as particles.xyz
// (output.particles_precision).
#include "engine/io/lammps_dump_writer.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/particle_file_output.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

constexpr Key<bool> lammps_dump{"output.lammps_dump"};

void declare(Schema& s) {
  s.table("output").add_bool(lammps_dump, false,
                             "write every frame's particles to particles.lammpstrj, a LAMMPS text dump (id type radius "
                             "x y z vx vy vz omegax omegay omegaz mass) for LAMMPS read_dump/rerun and OVITO");
}

std::unique_ptr<RunOutput> open(const OutputContext& c) {
  if (!c.scene.get(lammps_dump)) return nullptr;
  c.claim("particles.lammpstrj");
  return std::make_unique<ParticleFileOutput<io::LammpsDumpWriter>>(c.dir / "particles.lammpstrj",
                                                                    particle_precision(c.scene));
}

}  // namespace

OutputEntry lammps_dump_output() {
  return {"lammps_dump", "particles.lammpstrj, a LAMMPS text dump of every frame", &declare, nullptr, &open};
}

}  // namespace grainflow::scenes
