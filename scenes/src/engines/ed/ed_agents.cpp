#include "scenes/src/engines/ed/ed_agents.hpp"

#include <array>

namespace grainflow::scenes {

// Each agent's row, defined in its own file in agents/.
EdAgentEntry obstacle_agent();
EdAgentEntry stream_agent();
EdAgentEntry walls_agent();
EdAgentEntry thermostat_agent();
EdAgentEntry phases_agent();
EdAgentEntry medium_agent();

std::span<const EdAgentEntry> ed_agents() {
  // Attached in this order; the obstacle's key table precedes the stream's in scene.toml.
  // The walls only configure the box walls the simulation built (no disk changes). The
  // thermostat draws its first waiting time with the disks the obstacle and the stream
  // boundaries left. The phases come after every agent they may change. The medium only
  // reads the scene (Re, Ma).
  static const std::array<EdAgentEntry, 6> table = {obstacle_agent(), stream_agent(),  walls_agent(),
                                                    thermostat_agent(), phases_agent(), medium_agent()};
  return table;
}

}  // namespace grainflow::scenes
