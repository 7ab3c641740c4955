// The high-density inlet of seed 003 §3.3 (Fig. 3.9): a hard plane (piston) at x = X(t)
// moving at the stream velocity U clears a strip one disk diameter wide; a recharge timer
// then places a monolayer at the stream's area fraction in it and the piston jumps back.
#pragma once
#include <cstdint>
#include <memory>

#include "engine/core/rng.hpp"
#include "engine/ed/arrival_temperature.hpp"
#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

enum class PistonKind { elastic, thermal };

struct DispenserConfig {
  double U = 0.0;              // piston (= stream) velocity along +x, ≥ 0; 0: no recharge ever
  double kT = 0.02;            // stream temperature: new disks and the thermal piston
  double area_fraction = 0.65; // stream η; a monolayer of width 2R holds η·2R·Ly/(πR²) disks
  double radius = 0.5, mass = 1.0;
  bool rotation = false;       // rough disks: new disks get ω from N(0, kT/I), I = q m R²
  double q = 0.5;
  PistonKind piston = PistonKind::elastic;
  // New disks (and the thermal piston) at the temperature of the disks hitting the piston
  // (ArrivalTemperature over `window` hits, starting from kT) instead of kT: the upstream
  // stream cools as the simulated one does once the disks turn inelastic (seed ch. 5).
  bool local_kT = false;
  double window = 100.0;
  std::uint64_t seed = 1;
};

// The piston: a ParticleAgent living in the cells of the strip it sweeps.
class DispenserPiston final : public ParticleAgent {
public:
  // t0: start of the first cycle; ly, periodic_y: the inlet line.
  DispenserPiston(const DispenserConfig& cfg, double t0, double ly, bool periodic_y);
  std::string_view name() const override { return "dispenser piston"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i, const DiskNow& d) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  double strip() const { return strip_; }               // width swept per cycle (one diameter)
  double position(double t) const { return cfg_.U * (t - t_cycle_); }
  double recharge_time() const { return t_recharge_; }  // kNever when U = 0
  // The recharge: places the monolayer in [0, strip], jumps back, re-predicts the strip.
  void recharge(SystemState& state);
  std::uint64_t hits() const { return hits_; }
  double impulse_x() const { return impulse_x_; }       // momentum given to the disks along x
  std::uint64_t cycles() const { return cycles_; }
  double kT() const { return cfg_.local_kT ? arrivals_.kT() : cfg_.kT; }  // of the disks it places now

private:
  DispenserConfig cfg_;
  double ly_;
  bool periodic_y_;
  double strip_;
  double t_cycle_, t_recharge_;
  double owed_ = 0.0;  // fractional disk carried to the next monolayer, so the mean flux is exact
  core::Rng rng_;
  std::vector<int> cells_;
  std::vector<double> gaps_;
  std::uint64_t hits_ = 0, cycles_ = 0;
  double impulse_x_ = 0.0;
  ArrivalTemperature arrivals_;  // local_kT
};

// The recharge timer (the second agent of a dispenser, §3.3): fires when the piston has
// swept its strip.
class DispenserRecharge final : public TimerAgent {
public:
  explicit DispenserRecharge(DispenserPiston& piston) : piston_(piston) {}
  std::string_view name() const override { return "dispenser recharge"; }
  double event_time(const SystemState&) const override { return piston_.recharge_time(); }
  void action(SystemState& state) override { piston_.recharge(state); }
  // Nothing of its own: its clock is the piston's recharge time, saved with the piston.
  void save(io::ArchiveWriter&) const override {}
  void load(io::ArchiveReader&) override {}

private:
  DispenserPiston& piston_;
};

}  // namespace grainflow::ed
