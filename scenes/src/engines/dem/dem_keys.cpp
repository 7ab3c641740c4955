// Provisional [system]/[boundary] schema of the 3D soft-sphere DEM engine (seed 000
// ch. 2–5). Units: SI (m, kg, s, N, J). The DEM engine owns the physics; adjust the keys
// here as the engine grows.
#include <array>
#include <string>

#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {

void add_dem_schema(Schema& s) {
  s.table("sample").add_enum("plane", {"xy", "xz", "yz"}, "xz",
                             "plane the 3D fields are projected on (bins span the plane, averaged across)");
  auto& out = s.table("output");
  out.add_bool("pair_csv", false,
               "write pair.csv: step, time [s], separation α [m] (negative = overlap), normal_force, vdw_force, "
               "contact_force [N] (along the line of centres, positive = repulsive) and v_rel_n [m/s] "
               "(positive = separating) of particles 1 and 2 — the force–separation curve of seed 000 §5.4");
  out.add_int("pair_every", 1, "steps between pair.csv rows").at_least(1);

  auto& sys = s.section("system", "3D soft spheres: box, integration, gravity (seed 000 §2)");
  sys.add_float_array("box", {0.1, 0.1, 0.1}, {"Lx", "Ly", "Lz"}, "domain size", "m").above(0.0);
  sys.add_float_array("gravity", {0.0, 0.0, -9.81}, {"gx", "gy", "gz"}, "gravitational acceleration", "m/s²");
  sys.add_float("dt", 0.0, "time step; when absent it follows from steps_per_collision (Eq. 2.23)", "s")
      .above(0.0)
      .optional();
  sys.add_int("steps_per_collision", 50, "steps per binary collision n, used when dt is absent (§2.5: 40–60)")
      .at_least(5)
      .at_most(10000);

  sys.add_enum("neighbor_search", {"chain_cells", "all_pairs"}, "chain_cells",
               "how the Verlet table is built: chain cells (§3.2–3.4) or the N² reference search (validation; "
               "both give bit-identical trajectories)");
  sys.add_float("skin", 0.0, "Verlet search distance beyond contact (0 = 0.2 × the largest diameter)", "m")
      .at_least(0.0);

  auto& contact = s.section("system.contact", "contact model between particles and with walls (§2.4)");
  contact.add_enum("model", {"walton", "hooke"}, "walton",
                   "walton: partially latching spring + incrementally slipping friction; hooke: linear spring-dashpot");
  contact.add_float("kn", 1.0e4, "normal loading stiffness K1", "N/m").above(0.0);
  contact.add_float("kt", 8.0e3, "initial tangential stiffness", "N/m").above(0.0);
  contact.add_float("e", 0.9, "normal restitution e = sqrt(K1/K2) (Eq. 2.9)").above(0.0).at_most(1.0);
  contact.add_float("mu", 0.3, "Coulomb friction coefficient").at_least(0.0);

  auto& group = s.array_table("system.group", "a particle species: size, density, count (§2.2: two groups)");
  group.min_count = 1;
  group.add_int("N", 1000, "number of particles in the group").at_least(1);
  group.add_float("radius", 1.0e-3, "particle radius", "m").above(0.0);
  group.add_float("density", 2500.0, "material density", "kg/m³").above(0.0);
  group.add_float("e", 0.0, "normal restitution of this group's contacts (0 = use system.contact.e)")
      .at_least(0.0)
      .at_most(1.0);
  group.add_float("mu", -1.0, "friction of this group's contacts (negative = use system.contact.mu)");

  auto& vdw = s.optional_table("system.vdw", "van der Waals cohesion, Eq. 5.29 (ch. 5)");
  vdw.add_float("A", 1.0e-19, "Hamaker constant", "J").at_least(0.0);
  vdw.add_float("alpha_min", 4.0e-10, "separation below which the force is held constant", "m").above(0.0);
  vdw.add_float("cutoff", 1.0e-6, "separation beyond which the force is zero", "m").above(0.0);
  vdw.add_float("asperity_radius", 0.0, "radius R in the force law (0 = particle radius)", "m").at_least(0.0);
  vdw.add_float("r_ss", 0.0, "repulsive length r_ss of Eq. 5.28 (0 = attraction only)", "m").at_least(0.0);

  auto& init = s.section("system.initial", "initial positions (§2.2)");
  init.add_enum("kind", {"lattice", "random", "file"}, "random",
                "cubic lattice, random non-overlapping with radius growth (FINDRAD), or read from a file");
  init.add_string("file", "",
                  "particle file (XYZ or LAMMPS dump) for kind = \"file\", path relative to the scene file: its first "
                  "frame gives positions, radii (0 or no radius column = the group's radius) and velocities; type t "
                  "is group t − 1 and each group's N must equal its type's count")
      .path();
  init.add_int("grow_steps", 1000, "steps of radius growth from small to final radius (random placement)")
      .at_least(0);

  auto& bnd = s.section("boundary", "box walls and periodic axes (seed 000 §2.1)");
  bnd.add_bool_array("periodic", {false, false, false}, {"x", "y", "z"}, "periodic axes; others have walls");
  bnd.add_enum("top", {"closed", "open"}, "closed", "whether the top (z = Lz) has a wall");
  bnd.add_float_array("top_velocity", {0.0, 0.0}, {"vx", "vy"},
                      "in-plane velocity of the top wall (z = Lz), e.g. plane Couette shear", "m/s");
  bnd.add_float_array("bottom_velocity", {0.0, 0.0}, {"vx", "vy"}, "in-plane velocity of the bottom wall (z = 0)",
                      "m/s");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (sc.get<std::string>("system.initial.kind") == "file" && sc.get<std::string>("system.initial.file").empty())
      c.fail("system.initial.file", "system.initial.kind = \"file\" needs system.initial.file = \"path\"");
    if (sc.has("system.vdw") && sc.get<double>("system.vdw.cutoff") <= sc.get<double>("system.vdw.alpha_min"))
      c.fail("system.vdw.cutoff", "system.vdw.cutoff = " + toml_float(sc.get<double>("system.vdw.cutoff")) +
                                      " must exceed system.vdw.alpha_min = " +
                                      toml_float(sc.get<double>("system.vdw.alpha_min")));
    const auto periodic = sc.get<std::array<bool, 3>>("boundary.periodic");
    for (const char* key : {"boundary.top_velocity", "boundary.bottom_velocity"}) {
      const auto v = sc.get<std::array<double, 2>>(key);
      if (v[0] == 0.0 && v[1] == 0.0) continue;
      if (periodic[2])
        c.fail(key, std::string(key) + " = [" + toml_float(v[0]) + ", " + toml_float(v[1]) +
                        "] needs a wall there, but boundary.periodic makes z periodic; allowed: [0.0, 0.0]");
      else if (std::string(key) == "boundary.top_velocity" && sc.get<std::string>("boundary.top") == "open")
        c.fail(key, "boundary.top_velocity = [" + toml_float(v[0]) + ", " + toml_float(v[1]) +
                        "] needs a top wall, but boundary.top = \"open\"; allowed: [0.0, 0.0]");
    }
    if (sc.get<bool>("output.pair_csv")) {
      std::int64_t total = 0;
      for (std::size_t g = 0; g < sc.count("system.group"); ++g)
        total += sc.get<std::int64_t>("system.group[" + std::to_string(g) + "].N");
      if (total < 2)
        c.fail("output.pair_csv", "output.pair_csv = true needs at least 2 particles; the groups hold " +
                                      std::to_string(total));
    }
    const auto box = sc.get<std::array<double, 3>>("system.box");
    for (std::size_t g = 0; g < sc.count("system.group"); ++g) {
      const std::string key = "system.group[" + std::to_string(g) + "].radius";
      const double r = sc.get<double>(key);
      if (2 * r * 3 > std::min({box[0], box[1], box[2]}))
        c.fail(key, key + " = " + toml_float(r) + " is too large for the box; allowed: diameter ≤ min(Lx, Ly, Lz)/3");
    }
  });
}

}  // namespace grainflow::scenes
