// Declarations of the ED engine's keys (ed_keys.hpp): type, default, range, doc, unit, and
// the rules that involve several keys. ed_runner.cpp reads them through the same handles.
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes::ed_keys {

namespace {
// Densest packing of equal disks (hexagonal), π/(2√3): no configuration can exceed it.
constexpr double kMaxAreaFraction = std::numbers::pi / (2.0 * std::numbers::sqrt3);
}  // namespace

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
  sys.add_enum(calendar, {"bucket", "cell_heap"}, "bucket",
               "event calendar: bucket queue of one event per disk (fastest), or the seed's heap of cells (§2.4)");
  sys.add_float(cell_size, 1.2, "target side of the cells (§2.2: ≈ 1.2 σ at η = 0.65)", "σ")
      .above(1.0)
      .with_note("cells must be larger than a disk diameter");
  s.add_check([](const Scene& sc, SceneCheck& c) {
    const int given = int(sc.has(area_fraction)) + int(sc.has(n)) + int(sc.has(N));
    if (given != 1)
      c.fail(area_fraction.path, "give exactly one of system.area_fraction, system.n or system.N (" +
                                         std::to_string(given) + " given)");
    if (sc.has(n) && sc.get(n) * std::numbers::pi / 4.0 >= kMaxAreaFraction)
      c.fail(n.path, "system.n = " + toml_float(sc.get(n)) +
                             " exceeds close packing; allowed: n < 2/√3 ≈ 1.1547 (area fraction < 0.9069)");
  });

  auto& bnd = s.section("boundary", "edges of the domain, the obstacle and the stream inlet/outlet (seed 003 §3)");
  bnd.add_bool_array(periodic, {true, true}, {"x", "y"}, "periodic axes; a non-periodic axis has elastic walls, except x with an open "
                      "boundary.stream.kind (the inlet/outlet close it)");

  auto& obs = s.optional_table(obstacle, "fixed circular obstacle (§3.3, §5)");
  obs.add_float(obstacle_D, 74.0, "obstacle diameter", "σ").above(0.0);
  obs.add_float(obstacle_x, 0.0, "obstacle centre x (box origin at the lower left corner)", "σ").required();
  obs.add_float(obstacle_y, 0.0, "obstacle centre y", "σ").required();
  obs.add_enum(obstacle_kind, {"slip", "noslip_thermal", "noslip_flip"}, "slip",
               "surface: specular slip, no-slip by thermal re-emission, or no-slip by tangential flip");
  obs.add_float(obstacle_r, 1.0, "restitution of the obstacle surface (slip)").above(0.0).at_most(1.0);

  auto& stream = s.section("boundary.stream", "how disks enter at x = 0 and leave at x = Lx (§3.1–3.3); the "
                                              "stream's velocity, temperature and density are system.U, kT and "
                                              "the system's area fraction");
  stream.add_enum(stream_kind, {"periodic", "low_density", "dispenser_filter"}, "periodic",
                  "periodic in x, low-density inlet/outlet by flux distributions (§3.2), or dispenser piston + "
                  "filter (§3.3, dense streams)");
  stream.add_float(filter_distance, 3.0,
                   "dispenser_filter: distance of the filter plane before the outlet x = Lx; disks crossing it "
                   "are turned back or frozen at the stream velocity (Fig. 3.8)",
                   "σ")
      .above(0.5)
      .with_note("more than a disk radius (seed §3.3)");
  stream.add_enum(piston, {"elastic", "thermal"}, "elastic",
                  "dispenser_filter: the inlet piston reflects disks specularly in its frame, or re-emits them at "
                  "system.kT (Fig. 3.9)");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    const auto L = sc.get(box);
    if (sc.has(obstacle)) {
      const double R = sc.get(obstacle_D) / 2;
      const double x = sc.get(obstacle_x), y = sc.get(obstacle_y);
      if (x - R < 0 || x + R > L[0] || y - R < 0 || y + R > L[1])
        c.fail(obstacle_x.path, "obstacle of diameter " + toml_float(2 * R) + " at (" + toml_float(x) + ", " +
                                          toml_float(y) + ") does not fit in the box [" + toml_float(L[0]) +
                                          ", " + toml_float(L[1]) + "]; allowed: R ≤ x ≤ Lx − R, R ≤ y ≤ Ly − R");
    }
    const double cell = sc.get(cell_size);
    if (cell * 3 > std::min(L[0], L[1]))
      c.fail(cell_size.path, "system.cell_size = " + toml_float(cell) +
                                     " leaves fewer than 3 cells across the box; allowed: cell_size ≤ min(Lx, Ly)/3");
    const auto axes = sc.get(periodic);
    const std::string kind = sc.get(stream_kind);
    if (kind == "dispenser_filter") {
      const double fd = sc.get(filter_distance);
      if (fd >= L[0] / 2)
        c.fail(filter_distance.path,
               "boundary.stream.filter_distance = " + toml_float(fd) + " leaves no stream before the filter; allowed: "
               "filter_distance < Lx/2 = " + toml_float(L[0] / 2));
      const double eta = sc.has(area_fraction) ? sc.get(area_fraction)
                         : sc.has(n)             ? sc.get(n) * std::numbers::pi / 4
                         : sc.has(N) ? double(sc.get(N)) * std::numbers::pi / 4 /
                                                    (L[0] * L[1])
                                              : 0.0;
      if (eta >= std::numbers::pi / 4)
        c.fail(area_fraction.path, "area fraction " + toml_float(eta) +
                                           " with boundary.stream.kind = \"dispenser_filter\": the dispenser's "
                                           "monolayer cannot hold it; allowed: area fraction < π/4 ≈ 0.785");
      if (sc.get(U) < 0)
        c.fail(U.path, "system.U = " + toml_float(sc.get(U)) +
                               " with boundary.stream.kind = \"dispenser_filter\"; allowed: U ≥ 0 (the stream runs "
                               "along +x)");
      if (sc.has(obstacle)) {
        const double R = sc.get(obstacle_D) / 2, x = sc.get(obstacle_x);
        if (x + R + 2 > L[0] - fd || x - R - 2 < 1)
          c.fail(obstacle_x.path, "obstacle at x = " + toml_float(x) + " with D = " + toml_float(2 * R) +
                                            " reaches the dispenser strip [0, 1] or the filter at Lx − filter_distance "
                                            "= " + toml_float(L[0] - fd) + "; allowed: 3 + R ≤ x ≤ Lx − "
                                            "filter_distance − 2 − R");
      }
    }
    if (kind != "periodic" && axes[0])
      c.fail(periodic.path, "boundary.stream.kind = \"" + sc.get(stream_kind) +
                                      "\" needs an open x axis; allowed: boundary.periodic = [false, …]");
  });
}

}  // namespace grainflow::scenes::ed_keys
