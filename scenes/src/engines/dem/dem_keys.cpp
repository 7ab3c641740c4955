// Declarations of the DEM engine's keys (dem_keys.hpp): type, default, range, doc, unit,
// and the rules that involve several keys. dem_runner.cpp reads them through the same
// handles.
#include <algorithm>
#include <array>
#include <string>

#include "engine/dem/contact_params.hpp"
#include "scenes/src/engines/dem/dem_keys.hpp"
#include "scenes/src/engines/initial_file.hpp"
#include "scenes/src/engines/memory_budget.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes::dem_keys {

namespace {
// "a: what a does; b: what b does" from a sub-model table, for the key's doc.
std::string table_doc(std::span<const dem::SubModelInfo> rows) {
  std::string s;
  for (const auto& r : rows) s += (s.empty() ? "" : "; ") + std::string(r.name) + ": " + std::string(r.description);
  return s;
}
}  // namespace

void declare(Schema& s) {
  auto& sample = s.table("sample");
  sample.add_enum(plane, {"xy", "xz", "yz"}, "xz",
                  "plane the 3D fields are projected on (bins span the plane, averaged across the slab)");
  sample.add_float_array(slab, {0.0, 0.0}, {"lo", "hi"},
                         "the slab the fields average over: particles with lo ≤ coordinate across sample.plane < hi "
                         "(y for xz, z for xy, x for yz); absent: the whole box across",
                         "m")
      .optional();
  auto& out = s.table("output");
  out.add_bool(pair_csv, false,
               "write pair.csv: step, time [s], separation α [m] (negative = overlap), normal_force, vdw_force, "
               "contact_force [N] (along the line of centres, positive = repulsive) and v_rel_n [m/s] "
               "(positive = separating) of particles 1 and 2 — the force–separation curve of seed 000 §5.4");
  out.add_int(pair_every, 1, "steps between pair.csv rows").at_least(1);

  auto& sys = s.section("system", "3D soft spheres: box, integration, gravity (seed 000 §2)");
  sys.add_float_array(box, {0.1, 0.1, 0.1}, {"Lx", "Ly", "Lz"}, "domain size", "m").above(0.0);
  sys.add_float_array(origin, {0.0, 0.0, 0.0}, {"x0", "y0", "z0"},
                      "lower corner of the box: the domain is origin … origin + box (a LAMMPS region block xlo xhi "
                      "… is origin = [xlo, ylo, zlo], box = [xhi − xlo, …])",
                      "m");
  sys.add_float_array(gravity, {0.0, 0.0, -9.81}, {"gx", "gy", "gz"}, "gravitational acceleration", "m/s²");
  sys.add_float(dt, 0.0,
                "time step, used exactly as given (t = step × dt); when absent it follows from steps_per_collision "
                "(Eq. 2.23)",
                "s")
      .above(0.0)
      .optional();
  sys.add_int(steps_per_collision, 50, "steps per binary collision n, used when dt is absent (§2.5: 40–60)")
      .at_least(5)
      .at_most(10000);

  sys.add_enum(neighbor_search, {"chain_cells", "all_pairs"}, "chain_cells",
               "how the Verlet table is built: chain cells (§3.2–3.4) or the N² reference search (validation; "
               "both give bit-identical trajectories)");
  sys.add_float(skin, 0.0, "Verlet search distance beyond contact (0 = 0.2 × the largest diameter)", "m")
      .at_least(0.0);

  auto& contact = s.section("system.contact", "contact model between particles and with walls (§2.4)");
  contact.add_enum(normal_model, dem::normal_model_names(), "walton",
                   "normal force: " + table_doc(dem::sub_models<dem::NormalKind>()));
  contact.add_enum(tangential_model, dem::tangential_model_names(), "walton",
                   "tangential force: " + table_doc(dem::sub_models<dem::TangentialKind>()));
  contact.add_float(kn, 1.0e4, "normal loading stiffness K1 (LAMMPS Kn)", "N/m").above(0.0);
  contact.add_float(kt, 8.0e3, "initial tangential stiffness: Walton's K0, LAMMPS Kt", "N/m").above(0.0);
  contact.add_float(e, 0.9,
                    "normal restitution: walton K2 = K1/e² (Eq. 2.9) unless k2 is given; hooke γn from e unless "
                    "gamma_n is given")
      .above(0.0)
      .at_most(1.0);
  contact.add_float(mu, 0.3, "Coulomb friction coefficient (LAMMPS xmu)").at_least(0.0);
  contact.add_float(gamma_n, 0.0,
                    "hooke: normal damping γn (LAMMPS gamma_n; force m_eff·γn·v_n); absent: derived from e for a "
                    "pair of the group",
                    "1/s")
      .at_least(0.0)
      .optional();
  contact.add_float(gamma_t, 0.0,
                    "history: tangential damping γt (LAMMPS gamma_t; force m_eff·γt·v_t); absent: γn/2 (LAMMPS NULL)",
                    "1/s")
      .at_least(0.0)
      .optional();
  contact.add_bool(dampflag, true, "history: tangential damping on (LAMMPS dampflag 1) or off (0: γt = 0)");
  contact.add_float(k2, 0.0, "walton: unloading stiffness K2 (Eq. 2.1); absent: K1/e² (Eq. 2.9), given: e = "
                             "sqrt(K1/K2) and system.contact.e is not used by the normal model",
                    "N/m")
      .above(0.0)
      .optional();
  contact.add_float(walton_gamma, 1.0 / 3.0, "walton tangential: the exponent γ of K_T (Eq. 2.10; 1 = linear in T)")
      .above(0.0)
      .at_most(10.0);

  // The mixing rule is engine/dem's (contact_params.hpp: each coefficient block's mix()).
  auto& groups = s.array_table(
      group,
      "a particle species: size, density, count (§2.2: two groups) and optionally its own contact coefficients, "
      "which apply within the group and at the walls; between two groups each coefficient is the arithmetic mean "
      "of the two groups' values, and a γn, γt or K2 that either group derives stays derived (from the mean e); "
      "dampflag and the sub-models are system-wide");
  groups.min_count = 1;
  groups.add_int(group_N, 1000, "number of particles in the group").at_least(1);
  groups.add_float(group_radius, 1.0e-3, "particle radius", "m").above(0.0);
  groups.add_float(group_density, 2500.0, "material density", "kg/m³").above(0.0);
  groups.add_float(group_e, 0.0, "normal restitution of this group's contacts (0 = use system.contact.e)")
      .at_least(0.0)
      .at_most(1.0);
  groups.add_float(group_mu, -1.0, "friction of this group's contacts (negative = use system.contact.mu)");
  groups.add_float(group_kn, 0.0, "K1 / Kn of this group's contacts (0 = use system.contact.kn)", "N/m").at_least(0.0);
  groups.add_float(group_kt, 0.0, "K0 / Kt of this group's contacts (0 = use system.contact.kt)", "N/m").at_least(0.0);
  groups.add_float(group_k2, 0.0, "walton K2 of this group's contacts (0 = use system.contact.k2 or K1/e²)", "N/m")
      .at_least(0.0);
  groups.add_float(group_gamma_n, -1.0, "hooke γn of this group's contacts (negative = use system.contact.gamma_n)",
                   "1/s");
  groups.add_float(group_gamma_t, -1.0, "history γt of this group's contacts (negative = use system.contact.gamma_t)",
                   "1/s");

  auto& cohesion = s.optional_table(vdw, "van der Waals cohesion, Eq. 5.29 (ch. 5)");
  cohesion.add_float(vdw_A, 1.0e-19, "Hamaker constant", "J").at_least(0.0);
  cohesion.add_float(vdw_alpha_min, 4.0e-10, "separation at and below which the force is zero, overlap included (Eq. 5.29; §5.3 puts it at the zero of "
                    "Eq. 5.28, r_ss/60^(1/6))",
                    "m").above(0.0);
  cohesion.add_float(vdw_cutoff, 1.0e-6, "separation beyond which the force is zero", "m").above(0.0);
  cohesion.add_float(vdw_asperity_radius, 0.0, "radius R in the force law (0 = particle radius)", "m").at_least(0.0);
  cohesion.add_float(vdw_r_ss, 0.0, "repulsive length r_ss of Eq. 5.28 (0 = attraction only, which then stops abruptly at alpha_min)",
                    "m").at_least(0.0);

  auto& init = s.section("system.initial", "initial positions (§2.2)");
  init.add_enum(initial_kind, {"lattice", "random", "file"}, "random",
                "lattice: simple cubic through the box (a free fall from it stacks columns); random: random "
                "sequential addition at grow_from × the radius, then radius growth over grow_steps (FINDRAD, "
                "§2.1), a disordered bed once settled; file: read from a file");
  initial_file::declare(init, "positions, velocities, angular velocities (omegax omegay omegaz), radii (0 or "
                              "none = the group's radius) and masses (checked against radius and density); type t "
                              "is group t − 1 and each group's N must equal its type's count");
  init.add_int(grow_steps, 1000, "steps of radius growth from small to final radius (random placement)")
      .at_least(0);
  init.add_float(grow_from, 0.5,
                 "random: the radius fraction the spheres are placed at (random sequential addition, no overlap) "
                 "and grow from, linearly over grow_steps, while the contacts push them apart")
      .above(0.0)
      .at_most(1.0);
  init.add_float(fill_height, 0.0,
                 "random: centres are placed in the lowest fill_height of the box (z from origin.z); absent: the "
                 "whole box",
                 "m")
      .above(0.0)
      .optional();

  auto& bnd = s.section("boundary", "box walls and periodic axes (seed 000 §2.1)");
  bnd.add_bool_array(periodic, {false, false, false}, {"x", "y", "z"}, "periodic axes; others have walls");
  bnd.add_enum(top, {"closed", "open"}, "closed", "whether the top (z = Lz) has a wall");
  bnd.add_float_array(top_velocity, {0.0, 0.0}, {"vx", "vy"},
                      "in-plane velocity of the top wall (z = Lz), e.g. plane Couette shear", "m/s");
  bnd.add_float_array(bottom_velocity, {0.0, 0.0}, {"vx", "vy"}, "in-plane velocity of the bottom wall (z = 0)",
                      "m/s");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (sc.get(initial_kind) == "file" && sc.get(initial_file::file).empty())
      c.fail(initial_file::file.path, "system.initial.kind = \"file\" needs system.initial.file = \"path\"");
    if (const auto across = sc.find(slab)) {
      const auto L = sc.get(box);
      const auto o = sc.get(origin);
      const std::string p = sc.get(plane);
      const int n = p == "xy" ? 2 : p == "xz" ? 1 : 0;
      const double lo = o[std::size_t(n)], hi = lo + L[std::size_t(n)];
      const auto [a, b] = *across;
      if (!(a < b) || !(b > lo) || !(a < hi))
        c.fail(slab.path, "sample.slab = [" + toml_float(a) + ", " + toml_float(b) + "] must have lo < hi and "
                          "overlap the box across sample.plane = \"" + p + "\" (" + "xyz"[n] + " from " +
                          toml_float(lo) + " to " + toml_float(hi) + " m); allowed: lo < hi within that range");
    }
    if (const auto h = sc.find(fill_height); h && *h > sc.get(box)[2])
      c.fail(fill_height.path, "system.initial.fill_height = " + toml_float(*h) + " m is taller than the box (Lz = " +
                                   toml_float(sc.get(box)[2]) + " m); allowed: 0 < fill_height ≤ Lz");
    if (sc.find(fill_height) && sc.get(initial_kind) != "random")
      c.fail(fill_height.path, "system.initial.fill_height places random spheres, but system.initial.kind = \"" +
                                   sc.get(initial_kind) + "\"; allowed with kind = \"random\" only");
    if (sc.has(vdw) && sc.get(vdw_cutoff) <= sc.get(vdw_alpha_min))
      c.fail(vdw_cutoff.path, "system.vdw.cutoff = " + toml_float(sc.get(vdw_cutoff)) +
                                  " must exceed system.vdw.alpha_min = " + toml_float(sc.get(vdw_alpha_min)));
    const auto axes = sc.get(periodic);
    for (const auto& wall : {top_velocity, bottom_velocity}) {
      const auto v = sc.get(wall);
      if (v[0] == 0.0 && v[1] == 0.0) continue;
      const std::string value = std::string(wall.path) + " = [" + toml_float(v[0]) + ", " + toml_float(v[1]) + "]";
      if (axes[2])
        c.fail(wall.path, value + " needs a wall there, but boundary.periodic makes z periodic; allowed: [0.0, 0.0]");
      else if (wall.path == top_velocity.path && sc.get(top) == "open")
        c.fail(wall.path, value + " needs a top wall, but boundary.top = \"open\"; allowed: [0.0, 0.0]");
    }
    if (sc.get(pair_csv)) {
      std::int64_t total = 0;
      for (std::size_t g = 0; g < sc.count(group); ++g) total += sc.get(group_N, g);
      if (total < 2)
        c.fail(pair_csv.path, "output.pair_csv = true needs at least 2 particles; the groups hold " +
                                  std::to_string(total));
    }
    double spheres = 0;
    for (std::size_t g = 0; g < sc.count(group); ++g) spheres += double(sc.get(group_N, g));
    // ≈ 1 kB a sphere: state, neighbour table with contact history, force slots.
    if (const std::string short_of = memory_shortfall(spheres, 1000.0, "spheres"); !short_of.empty())
      c.fail("system.group[0].N", short_of + "; allowed: fewer particles");
    const auto L = sc.get(box);
    for (std::size_t g = 0; g < sc.count(group); ++g) {
      const std::string key = "system.group[" + std::to_string(g) + "].radius";
      const double r = sc.get(group_radius, g);
      if (2 * r * 3 > std::min({L[0], L[1], L[2]}))
        c.fail(key, key + " = " + toml_float(r) + " is too large for the box; allowed: diameter ≤ min(Lx, Ly, Lz)/3");
    }
  });
}

}  // namespace grainflow::scenes::dem_keys
