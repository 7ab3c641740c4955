// Checkpoints of the ED engine: Simulation::save_state / load_state (simulation.hpp).
//
// Layout (io::ArchiveWriter, native byte order):
//   "ed.simulation"  what must match: calendar kind, box and boundaries, collision rule
//                    as constructed (set_restitution's value is state, in "ed.tc"),
//                    cell size, the number of disks built with, agent and timer names
//   "ed.agents"      per agent: its name as a tag, then its save()
//   "ed.timers"      per timer: the same
//   "ed.state"       SystemState::save (with "ed.tc": the TC model's restitution, cutoff,
//                    step, last-collision times and overlap log; "ed.cells": the cell
//                    membership)
//   "ed.end"
// The calendar is not saved: both calendars pop in the total order of (key, entry index),
// so EventLoopBase::resume rebuilds an equivalent one from the saved keys.
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

namespace {

template <class Agents>
std::vector<std::string> names_of(const Agents& agents) {
  std::vector<std::string> out;
  for (const auto& a : agents) out.emplace_back(a->name());
  return out;
}

std::string listed(const std::vector<std::string>& names) {
  std::string s = "[";
  for (std::size_t k = 0; k < names.size(); ++k) s += (k ? ", " : "") + names[k];
  return s + "]";
}

void write_names(io::ArchiveWriter& w, const std::vector<std::string>& names) {
  w.pod(static_cast<std::uint32_t>(names.size()));
  for (const std::string& n : names) w.string(n);
}

std::vector<std::string> read_names(io::ArchiveReader& r) {
  const auto n = r.get<std::uint32_t>();
  // Each name costs at least its 8-byte length: a corrupt count cannot reserve much.
  if (n > r.left() / 8) r.corrupt(fmt::format("a list of {} agent names in {} bytes", n, r.left()));
  std::vector<std::string> out;
  out.reserve(n);
  for (std::uint32_t k = 0; k < n; ++k) out.push_back(r.string());
  return out;
}

std::string box_text(double lx, double ly, bool px, bool py, bool open_x) {
  return fmt::format("{} x {} (x {}, y {})", lx, ly, px ? "periodic" : open_x ? "open" : "walls",
                     py ? "periodic" : "walls");
}

}  // namespace

void Simulation::save_state(io::ArchiveWriter& w) const {
  // ≈ 133 bytes a disk (bench_ed --checkpoint): one allocation, not a doubling series.
  w.reserve(static_cast<std::size_t>(s_.size()) * 140 + (1 << 16));
  w.tag("ed.simulation");
  w.string(calendar_name(cfg_.calendar));
  w.pod(cfg_.lx);
  w.pod(cfg_.ly);
  w.flag(cfg_.periodic_x);
  w.flag(cfg_.periodic_y);
  w.flag(cfg_.open_x);
  w.pod(cfg_.wall_restitution);
  w.pod(cfg_.e);
  w.pod(cfg_.e_t);
  w.pod(cfg_.mu);
  w.pod(cfg_.min_cell_size);
  w.pod(static_cast<std::int32_t>(n_built_));
  write_names(w, names_of(s_.agents));
  write_names(w, names_of(s_.timers));

  w.tag("ed.agents");
  for (const auto& a : s_.agents) {
    w.tag(a->name());
    a->save(w);
  }
  w.tag("ed.timers");
  for (const auto& t : s_.timers) {
    w.tag(t->name());
    t->save(w);
  }
  s_.save(w);
  w.tag("ed.end");
}

void Simulation::load_state(io::ArchiveReader& r) {
  // What must match, before anything is changed.
  r.tag("ed.simulation");
  const std::string cal = r.string();
  if (cal != calendar_name(cfg_.calendar))
    r.mismatch(fmt::format("the calendar is '{}' in the archive, '{}' here", cal, calendar_name(cfg_.calendar)));
  const double lx = r.get<double>(), ly = r.get<double>();
  const bool px = r.flag("periodic_x"), py = r.flag("periodic_y");
  const bool open_x = r.flag("open_x");
  if (lx != cfg_.lx || ly != cfg_.ly || px != cfg_.periodic_x || py != cfg_.periodic_y || open_x != cfg_.open_x)
    r.mismatch(fmt::format("the box is {} in the archive, {} here", box_text(lx, ly, px, py, open_x),
                           box_text(cfg_.lx, cfg_.ly, cfg_.periodic_x, cfg_.periodic_y, cfg_.open_x)));
  const double wall_r = r.get<double>();
  if (wall_r != cfg_.wall_restitution)
    r.mismatch(fmt::format("the wall restitution is {} in the archive, {} here", wall_r, cfg_.wall_restitution));
  const double e = r.get<double>(), e_t = r.get<double>(), mu = r.get<double>();
  if (e != cfg_.e || e_t != cfg_.e_t || mu != cfg_.mu)
    r.mismatch(fmt::format("the collision rule (e, e_t, mu) is ({}, {}, {}) in the archive, ({}, {}, {}) here", e, e_t,
                           mu, cfg_.e, cfg_.e_t, cfg_.mu));
  const double cell = r.get<double>();
  if (cell != cfg_.min_cell_size)
    r.mismatch(fmt::format("the minimum cell size is {} in the archive, {} here", cell, cfg_.min_cell_size));
  const auto n_built = r.get<std::int32_t>();
  if (n_built != n_built_)
    r.mismatch(fmt::format("the archive's simulation was built with {} disks, this one with {} (another N or area "
                           "fraction)", n_built, n_built_));
  const std::vector<std::string> agents = read_names(r), timers = read_names(r);
  if (agents != names_of(s_.agents))
    r.mismatch(fmt::format("the agents are {} in the archive, {} here (the same agents must be added in the same "
                           "order)", listed(agents), listed(names_of(s_.agents))));
  if (timers != names_of(s_.timers))
    r.mismatch(fmt::format("the timers are {} in the archive, {} here (the same timers must be added in the same "
                           "order)", listed(timers), listed(names_of(s_.timers))));

  // The agents load in place: keep their present state to put back if anything fails.
  std::vector<std::string> backup;
  for (const auto& a : s_.agents) {
    io::ArchiveWriter b;
    a->save(b);
    backup.push_back(b.take());
  }
  for (const auto& t : s_.timers) {
    io::ArchiveWriter b;
    t->save(b);
    backup.push_back(b.take());
  }
  SystemState::Saved saved;
  try {
    r.tag("ed.agents");
    for (const auto& a : s_.agents) {
      r.tag(a->name());
      a->load(r);
    }
    r.tag("ed.timers");
    for (const auto& t : s_.timers) {
      r.tag(t->name());
      t->load(r);
    }
    saved = s_.read_saved(r);
    r.tag("ed.end");
  } catch (...) {
    std::size_t k = 0;
    for (const auto& a : s_.agents) {
      io::ArchiveReader b(backup[k++], "the agent's own state");
      a->load(b);
    }
    for (const auto& t : s_.timers) {
      io::ArchiveReader b(backup[k++], "the timer's own state");
      t->load(b);
    }
    throw;
  }
  s_.restore(std::move(saved));
  loop_->resume();
}

}  // namespace grainflow::ed
