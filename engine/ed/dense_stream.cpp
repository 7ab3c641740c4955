#include "engine/ed/dense_stream.hpp"

#include <algorithm>
#include <numbers>

#include "engine/core/rng.hpp"

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"

namespace grainflow::ed {

DenseStream add_dense_stream(Simulation& sim, const DenseStreamConfig& cfg) {
  const Config& c = sim.config();
  if (!c.open_x)
    throw Error("ed: the dispenser and filter need an open x axis (Config::open_x, scene boundary.periodic = "
                "[false, …] with boundary.stream.kind = \"dispenser_filter\")");
  SystemState& s = sim.state();
  double radius = 0.5, mass = 1.0;
  for (int i = 0; i < s.size(); ++i)
    if (s.present(i)) {
      radius = s.body[i].r;
      mass = s.body[i].m;
      break;
    }
  // The strip must lie well before the filter, the filter a radius before the outlet.
  if (!(cfg.filter_distance > radius && cfg.filter_distance < c.lx - 4.0 * radius))
    throw Error(fmt::format("ed: filter_distance = {} is invalid; allowed: {} < filter_distance < Lx − 4R = {}",
                            cfg.filter_distance, radius, c.lx - 4.0 * radius));
  DispenserConfig dc;
  dc.U = cfg.U;
  dc.kT = cfg.kT;
  dc.area_fraction = cfg.area_fraction;
  dc.radius = radius;
  dc.mass = mass;
  dc.rotation = c.mu > 0.0;
  dc.piston = cfg.piston;
  dc.seed = cfg.seed;
  FilterConfig fc;
  fc.lx = c.lx;
  fc.distance = cfg.filter_distance;
  fc.U = cfg.U;
  fc.kT = cfg.kT;
  fc.mass = mass;
  fc.delete_instead_of_freeze = cfg.delete_instead_of_freeze;
  // One monolayer of the stream: the disks one dispenser cycle brings in.
  const double window = std::max(1.0, cfg.area_fraction * 2.0 * radius * c.ly / (std::numbers::pi * radius * radius));
  dc.local_kT = fc.local_kT = cfg.local_kT;
  dc.window = fc.window = window;
  fc.seed = core::substream_seed(cfg.seed, 0x5151);
  auto piston = std::make_unique<DispenserPiston>(dc, sim.time(), c.ly, c.periodic_y);
  auto filter = std::make_unique<StreamFilter>(fc);
  sim.synchronise();
  const double xf = filter->plane();
  if (cfg.delete_instead_of_freeze) {
    sim.remove_disks_unless([&](int i) { return s.disk[i].x < xf; });
  } else {
    for (int i = 0; i < s.size(); ++i)
      if (s.present(i) && s.disk[i].x >= xf) s.freeze(i, cfg.U, 0.0);
  }
  DenseStream out;
  out.piston = static_cast<DispenserPiston*>(sim.add_agent(std::move(piston)));
  out.filter = static_cast<StreamFilter*>(sim.add_agent(std::move(filter)));
  out.recharge = static_cast<DispenserRecharge*>(sim.add_timer(std::make_unique<DispenserRecharge>(*out.piston)));
  return out;
}

}  // namespace grainflow::ed
