// The table of ED agents a scene can switch on (seed 003 §2.5: event sources besides the
// disks): each row declares the keys its agent consumes and attaches the agent to the
// simulation when the scene asks for it. What an attached agent adds to the run — shapes
// drawn over the disks, field bins it covers, stats columns, run.json figures — goes
// through EdAgentRun, so the runner knows no particular agent.
// Adding an agent: ARCHITECTURE.md, "an ED agent" (the agent and its test in engine/ed and
// tests/ed, one file in engines/ed/agents/ for its keys and its attach, one row in
// ed_agents.cpp, a case in tests/scenes/app_tables_test.cpp).
#pragma once
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/core/vec.hpp"
#include "render/snapshot.hpp"
#include "scenes/src/outputs/run_output.hpp"

namespace grainflow::ed {
class Simulation;
enum class ObstacleBoundary;
}
namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::scenes {

class Schema;
class Scene;

class EdAgentRun {
public:
  virtual ~EdAgentRun() = default;
  // Shapes to draw over the disks (the obstacle).
  virtual void draw(render::Snapshot& /*s*/) const {}
  // True when the field bin centred at p holds no gas (inside a solid, beyond a filter):
  // masked, not "empty".
  virtual bool solid(const Vec2& /*p*/) const { return false; }
  // The share of the time a disk centre (of radius `radius`) at p is free of a moving
  // boundary (the dispenser piston sweeping its strip): 1 where nothing moves. The open
  // area a bin's density is divided by weighs each point by it.
  virtual double open_share(const Vec2& /*p*/, double /*radius*/) const { return 1.0; }
  // stats.csv columns, and their values over the window of `duration` since the last row.
  virtual std::vector<StatsColumn> stats_columns() const { return {}; }
  virtual void stats_row(double /*duration*/, std::vector<double>& /*row*/) {}
  // "key = value" pairs for the frame's caption (the phase in effect).
  virtual void labels(std::vector<std::pair<std::string, std::string>>& /*out*/) const {}
  // Totals for run.json.
  virtual void figures(std::vector<std::pair<std::string, double>>& /*out*/) const {}
  // What the run keeps besides the agent's engine state (which the simulation's checkpoint
  // holds): e.g. the stats window's starting values. Every row must decide.
  virtual void save(io::ArchiveWriter& w) const = 0;
  virtual void load(io::ArchiveReader& r) = 0;
};

struct EdAgentEntry {
  std::string_view name;
  std::string_view description;
  void (*declare_keys)(Schema&);
  // Attaches the agent when the scene asks for it; nullptr when it does not.
  std::unique_ptr<EdAgentRun> (*attach)(const Scene&, ed::Simulation&);
};

std::span<const EdAgentEntry> ed_agents();

// The obstacle surface a scene names (boundary.obstacle.kind, phase.obstacle_kind: "slip",
// "noslip_thermal", "noslip_flip") and back; agents/obstacle.cpp.
ed::ObstacleBoundary obstacle_boundary(std::string_view kind);
std::string_view obstacle_kind_name(ed::ObstacleBoundary b);

}  // namespace grainflow::scenes
