#include "engine/ed/low_density_stream.hpp"

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"

namespace grainflow::ed {

LowDensityStream add_low_density_stream(Simulation& sim, const LowDensityStreamConfig& cfg) {
  const CellGrid& g = sim.state().grid;
  if (g.periodic_x())
    throw Error("open stream (low density): the x axis is periodic; inlet and outlet need a non-periodic x axis");
  const double x_out = cfg.x_out > 0.0 ? cfg.x_out : g.lx() - 1.0;
  // With walls across x the planes must keep disks a radius off them, so that the walls
  // never act (disks leave or turn at the planes first); an open x axis needs only the box.
  const double margin = sim.config().open_x ? 0.0 : cfg.radius;
  if (!(cfg.x_in >= margin) || !(x_out <= g.lx() - margin) || !(x_out > cfg.x_in))
    throw Error(fmt::format("open stream (low density): inlet x = {} and outlet x = {} must satisfy "
                            "{} ≤ inlet < outlet ≤ {} (box length {}{})",
                            cfg.x_in, x_out, margin, g.lx() - margin, g.lx(),
                            margin > 0.0 ? ", a radius off the x walls" : ""));
  LowDensityStream out;
  out.flux = std::make_shared<const StreamFlux>(cfg.U, cfg.kT, cfg.mass);

  StreamInletConfig in;
  in.x = cfg.x_in;
  in.y_min = g.periodic_y() ? 0.0 : cfg.radius;
  in.y_max = g.periodic_y() ? g.ly() : g.ly() - cfg.radius;
  in.number_density = cfg.number_density;
  in.radius = cfg.radius;
  in.max_tries = cfg.max_tries;
  in.seed = cfg.seed;
  in.t_start = sim.time();
  out.inlet = &sim.emplace_timer<StreamInlet>(in, out.flux);
  out.inlet_plane = static_cast<StreamInletPlane*>(sim.add_agent(std::make_unique<StreamInletPlane>(cfg.x_in)));

  StreamOutletConfig oc;
  oc.x = x_out;
  oc.turn_back = cfg.turn_back;
  oc.seed = cfg.seed ^ 0x9E3779B97F4A7C15ull;  // an independent stream for the outlet
  out.outlet = static_cast<StreamOutlet*>(sim.add_agent(std::make_unique<StreamOutlet>(oc, out.flux)));
  return out;
}

}  // namespace grainflow::ed
