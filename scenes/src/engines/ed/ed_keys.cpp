// Declarations of the ED engine's keys (ed_keys.hpp): type, default, range, doc, unit, and
// the rules that involve several keys. ed_runner.cpp reads them through the same handles.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/memory_budget.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/engines/initial_file.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes::ed_keys {

namespace {
// Densest packing of equal disks (hexagonal), π/(2√3): no configuration can exceed it.
constexpr double kMaxAreaFraction = std::numbers::pi / (2.0 * std::numbers::sqrt3);
}  // namespace

double requested_area_fraction(const Scene& sc) {
  const auto L = sc.get(box);
  if (sc.has(area_fraction)) return sc.get(area_fraction);
  if (sc.has(n)) return sc.get(n) * std::numbers::pi / 4;
  if (sc.has(N)) return double(sc.get(N)) * std::numbers::pi / 4 / (L[0] * L[1]);
  return 0.0;
}

std::string obstacle_kind_at(const Scene& sc, std::size_t k) {
  const std::size_t n = sc.count(phase);
  for (std::size_t j = std::min(k == std::size_t(-1) ? 0 : k + 1, n); j-- > 0;)
    if (sc.has("phase[" + std::to_string(j) + "].obstacle_kind")) return sc.get(phase_obstacle_kind, j);
  return sc.get(obstacle_kind);
}

bool obstacle_r_used(const Scene& sc, std::size_t from) {
  const std::size_t n = sc.count(phase);
  if (obstacle_kind_at(sc, from) != "noslip_thermal") return true;
  for (std::size_t j = from == std::size_t(-1) ? 0 : from + 1; j < n; ++j) {
    if (sc.has("phase[" + std::to_string(j) + "].obstacle_r")) return false;  // replaced before any use
    if (obstacle_kind_at(sc, j) != "noslip_thermal") return true;
  }
  return false;
}

void declare(Schema& s) {
  auto& sys = s.section("system", "2D hard disks: box, number of disks, collision rule (seed 003 §2, §3.4)");
  sys.add_float_array(box, {440.0, 440.0}, {"Lx", "Ly"}, "domain size; the stream flows along +x", "σ").above(0.0);
  sys.add_float(area_fraction, 0.0, "area fraction η of the disks (give one of area_fraction, n, N)")
      .above(0.0)
      .below(kMaxAreaFraction)
      .with_note("hexagonal close packing is π/(2√3) ≈ 0.9069")
      .optional();
  sys.add_float(n, 0.0, "number density (give one of area_fraction, n, N)", "1/σ²").above(0.0).optional();
  sys.add_int(N, 0, "number of disks (give one of area_fraction, n, N)").at_least(1).optional();
  sys.add_float(kT, 0.02, "initial granular temperature and inlet temperature", "m σ²/τ²").above(0.0);
  sys.add_float(U, 0.0, "stream velocity along +x (0 = no stream)", "σ/τ");
  sys.add_float(e, 1.0, "normal restitution coefficient (Eq. 3.52–3.55)").above(0.0).at_most(1.0);
  sys.add_float(e_t, 0.44, "tangential restitution coefficient (Eq. 3.63), used when mu > 0")
      .at_least(0.0)
      .at_most(1.0);
  sys.add_float(mu, 0.0, "Coulomb friction coefficient (Eq. 3.65); 0 = smooth disks, no rotation").at_least(0.0);
  // TC model (Luding & McNamara 1998; seed 003 ch. 5): off by default, so that e < 1
  // means exactly what it says; a dense inelastic scene without it collapses, and the run
  // then fails with a message saying so (collapse_events), never hangs.
  sys.add_float(tau_tc, 0.0,
                "TC model, with e < 1: a collision is elastic in its normal part when either disk collided less than "
                "tau_tc ago, so inelastic systems cannot collapse (0 = off; LM98 use 1e-4 … 1e-2 of the mean free "
                "time: ≈ 1e-4 at η = 0.65, kT = 0.02)",
                "τ")
      .at_least(0.0);
  sys.add_float(tau_tc_step, 0.0,
                "TC model, with e < 1: a disk found overlapping (or colliding inelastically faster than the clock "
                "resolves) is removed and tau_tc raised by this much (seed 003 ch. 5; 0 = tau_tc stays; tau_tc = 0 "
                "with a step > 0: the first such event sets the cutoff)",
                "τ")
      .at_least(0.0);
  sys.add_int(collapse_events, 10'000'000,
              "collapse guard: the run fails as collapsed when over this many events the clock advanced less than "
              "1e-6 of what the run's average time per event gives (0 = never; inelastic collapse, cure: tau_tc)")
      .at_least(0)
      .may_change_on_resume();  // it decides no bit of the state, only when a run gives up
  sys.add_enum(calendar, {"bucket", "cell_heap"}, "bucket",
               "event calendar: bucket queue of one event per disk (fastest), or the seed's heap of cells (§2.4)");
  sys.add_int(lanes, 1,
              "event loops the box is cut into, as bands of cell rows across y: 2 runs them on two threads where there "
              "are two cores (--threads 1: one), with the same results either way, though not the same bits as 1 "
              "lane; needs at least 16 rows of cells")
      .at_least(1)
      .at_most(2);
  sys.add_float(cell_size, 1.2, "target side of the cells (§2.2: ≈ 1.2 σ at η = 0.65)", "σ")
      .above(1.0)
      .with_note("cells must be larger than a disk diameter");
  auto& init = s.section("system.initial", "initial state (the melting lattice, or a particle file)");
  init.add_enum(initial_kind, {"lattice", "file"}, "lattice",
                "a triangular lattice at area_fraction | n | N that melts, with Maxwell velocities at kT plus U; or "
                "the disks of system.initial.file");
  initial_file::declare(init, "positions, radii (none: σ/2), velocities (none: Maxwell at kT plus U), spins "
                              "(omega or omegaz) and masses when present; the disks must lie inside system.box "
                              "without overlap");
  s.add_check([](const Scene& sc, SceneCheck& c) {
    const int given = int(sc.has(area_fraction)) + int(sc.has(n)) + int(sc.has(N));
    const bool from_file = sc.get(initial_kind) == "file";
    if (from_file && sc.get(initial_file::file).empty())
      c.fail(initial_file::file.path, "system.initial.kind = \"file\" needs system.initial.file = \"path\"");
    // With a file the density keys are not used (the runner says so when one is given, so
    // that `--set system.initial.kind=file` works on a scene written for the lattice).
    if (given > 1 || (!from_file && given != 1))
      c.fail(area_fraction.path, "give exactly one of system.area_fraction, system.n or system.N (" +
                                         std::to_string(given) + " given)");
    if (sc.has(n) && sc.get(n) * std::numbers::pi / 4.0 >= kMaxAreaFraction)
      c.fail(n.path, "system.n = " + toml_float(sc.get(n)) +
                             " exceeds close packing; allowed: n < 2/√3 ≈ 1.1547 (area fraction < 0.9069)");
  });

  auto& bnd = s.section("boundary", "edges of the domain, the obstacle and the stream inlet/outlet (seed 003 §3)");
  bnd.add_bool_array(periodic, {true, true}, {"x", "y"}, "periodic axes; a non-periodic axis has elastic walls, except x with an open "
                      "boundary.stream.kind (the inlet/outlet close it)");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    const auto L = sc.get(box);
    // The disks the scene asks for, against the engine's limit and this machine's memory
    // (≈ 165 B a disk in the engine, more while the initial state is built: 256 B).
    const double disks = requested_area_fraction(sc) * L[0] * L[1] / (std::numbers::pi / 4);
    const char* key = sc.has(N) ? N.path.data() : sc.has(n) ? n.path.data() : area_fraction.path.data();
    if (disks > double(std::numeric_limits<int>::max()))
      c.fail(key, fmt::format("the scene asks for {:.3g} disks; allowed: at most 2147483647 (2^31 − 1)", disks));
    else if (const std::string short_of = memory_shortfall(disks, 256.0, "disks"); !short_of.empty())
      c.fail(key, short_of + "; allowed: a smaller system.box or density");
    const double cell = sc.get(cell_size);
    // The cell grid (§2.2) costs memory whatever the density: ≈ 64 B a cell with its slots
    // and calendar share; cells are counted by int.
    const double cells = std::floor(L[0] / cell) * std::floor(L[1] / cell);
    if (cells > double(std::numeric_limits<int>::max()))
      c.fail(cell_size.path, fmt::format("system.box / system.cell_size gives {:.3g} cells; allowed: at most "
                                         "2147483647 (a smaller box or larger cells)",
                                         cells));
    else if (const std::string short_of = memory_shortfall(cells, 64.0, "cells of the grid"); !short_of.empty())
      c.fail(cell_size.path, short_of + "; allowed: a smaller system.box or a larger system.cell_size");
    if (cell * 3 > std::min(L[0], L[1]))
      c.fail(cell_size.path, "system.cell_size = " + toml_float(cell) +
                                 " leaves fewer than 3 cells across the box; allowed: cell_size ≤ min(Lx, Ly)/3");
  });
  // The agents' own keys (obstacle, stream boundaries, thermostat), in table order.
  for (const auto& a : ed_agents()) a.declare_keys(s);
}

}  // namespace grainflow::scenes::ed_keys
