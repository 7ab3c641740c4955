// The stream boundaries along x of seed 003 §3.1–3.3 ([boundary.stream]): periodic, a
// low-density inlet/outlet by flux distributions, or the dispenser piston + filter of a
// dense stream, with the system's U, kT and area fraction. Masks the bins beyond the filter.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "engine/core/rng.hpp"
#include "engine/io/archive.hpp"
#include "engine/ed/dense_stream.hpp"
#include "engine/ed/low_density_stream.hpp"
#include "engine/ed/simulation.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {
namespace {

using namespace ed_keys;

void declare_keys(Schema& s) {
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
  stream.add_bool(stream_local_kT, false,
                  "dispenser_filter: new disks (and the thermal piston) at the temperature of the disks hitting the "
                  "piston, and the filter's back flux at that of the disks arriving at it (running means of m v_y² "
                  "over one monolayer's worth of disks), instead of system.kT: for a stream that cools (inelastic "
                  "disks, seed ch. 5), whose continuation beyond either boundary cools as well");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    const auto L = sc.get(box);
    const auto axes = sc.get(periodic);
    const std::string kind = sc.get(stream_kind);
    if (kind == "dispenser_filter") {
      const double fd = sc.get(filter_distance);
      if (fd >= L[0] / 2)
        c.fail(filter_distance.path,
               "boundary.stream.filter_distance = " + toml_float(fd) + " leaves no stream before the filter; allowed: "
               "filter_distance < Lx/2 = " + toml_float(L[0] / 2));
      const double eta = requested_area_fraction(sc);
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

// The stream's area fraction as the scene gives it (one of area_fraction, n, N).
double stream_area_fraction(const Scene& sc, const ed::Config& c) {
  if (auto eta = sc.find(area_fraction)) return *eta;
  return double(c.n) * std::numbers::pi / 4.0 / (c.lx * c.ly);
}

// The inlet/outlet pair: nothing to draw or mask, and no state beyond its agents'.
class LowDensityStreamRun final : public EdAgentRun {
public:
  void save(io::ArchiveWriter&) const override {}
  void load(io::ArchiveReader&) override {}
};

class DenseStreamRun final : public EdAgentRun {
public:
  DenseStreamRun(ed::DenseStream d, bool local_kT) : dense_(d), local_kT_(local_kT) {}
  // Frozen disks beyond the filter are not sampled: no gas there.
  bool solid(const Vec2& p) const override { return dense_.filter && p.x() > dense_.filter->plane(); }
  // The piston sweeps its strip [0, s] at the stream speed and jumps back, so its position
  // X is uniform over [0, s] in time: a centre at x is free of it when x ≥ X + radius.
  double open_share(const Vec2& p, double radius) const override {
    if (!dense_.piston) return 1.0;
    return std::clamp((p.x() - radius) / dense_.piston->strip(), 0.0, 1.0);
  }
  // With local_kT: the temperatures the boundaries work at now.
  std::vector<StatsColumn> stats_columns() const override {
    if (!local_kT_) return {};
    return {{"kT_dispenser", "E", "temperature of the disks the dispenser places now (boundary.stream.local_kT)"},
            {"kT_filter", "E", "temperature of the filter's back flux now (boundary.stream.local_kT)"}};
  }
  void stats_row(double, std::vector<double>& row) override {
    if (!local_kT_) return;
    row.push_back(dense_.piston->kT());
    row.push_back(dense_.filter->kT());
  }
  void draw(render::Snapshot& s) const override {
    const double ly = s.hi.y();
    if (dense_.piston) {
      const double x = dense_.piston->position(s.time);
      s.boundary_lines.push_back({{x, 0.0}, {x, ly}});
    }
    if (dense_.filter) s.boundary_lines.push_back({{dense_.filter->plane(), 0.0}, {dense_.filter->plane(), ly}});
  }
  // Only pointers to agents, whose state the simulation's checkpoint holds.
  void save(io::ArchiveWriter&) const override {}
  void load(io::ArchiveReader&) override {}

private:
  ed::DenseStream dense_;  // agents owned by the simulation
  bool local_kT_;
};

std::unique_ptr<EdAgentRun> attach(const Scene& sc, ed::Simulation& sim) {
  const std::string kind = sc.get(stream_kind);
  const ed::Config& c = sim.config();
  const std::uint64_t seed = core::substream_seed(c.seed, 2);  // its own random streams
  if (kind == "dispenser_filter") {
    ed::DenseStreamConfig d;
    d.U = c.stream.x();
    d.kT = c.kT;
    d.area_fraction = stream_area_fraction(sc, c);
    d.filter_distance = sc.get(filter_distance);
    d.piston = sc.get(piston) == "thermal" ? ed::PistonKind::thermal : ed::PistonKind::elastic;
    d.local_kT = sc.get(stream_local_kT);
    d.seed = seed;
    return std::make_unique<DenseStreamRun>(ed::add_dense_stream(sim, d), d.local_kT);
  }
  if (kind == "low_density") {
    ed::LowDensityStreamConfig l;
    l.U = c.stream.x();
    l.kT = c.kT;
    l.number_density = stream_area_fraction(sc, c) / (std::numbers::pi / 4.0);
    l.seed = seed;
    const double x_out = c.lx - 1.0;
    sim.remove_disks_unless([&](int i) { return sim.disks()[i].x >= l.x_in && sim.disks()[i].x <= x_out; });
    ed::add_low_density_stream(sim, l);
    return std::make_unique<LowDensityStreamRun>();
  }
  return nullptr;  // periodic in x: nothing to attach
}

}  // namespace

EdAgentEntry stream_agent() {
  return {"stream", "stream boundaries along x: periodic, low-density inlet/outlet, dispenser + filter (§3.1–3.3)",
          &declare_keys, &attach};
}

}  // namespace grainflow::scenes
