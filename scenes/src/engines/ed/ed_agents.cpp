#include "scenes/src/engines/ed/ed_agents.hpp"

#include <array>

namespace grainflow::scenes {

// Each agent's row, defined in its own file in agents/.
EdAgentEntry obstacle_agent();
EdAgentEntry stream_agent();
EdAgentEntry thermostat_agent();

std::span<const EdAgentEntry> ed_agents() {
  // Attached in this order; the obstacle's key table precedes the stream's in scene.toml.
  // The thermostat comes last: it draws its first waiting time with the disks the obstacle
  // and the stream boundaries left.
  static const std::array<EdAgentEntry, 3> table = {obstacle_agent(), stream_agent(), thermostat_agent()};
  return table;
}

}  // namespace grainflow::scenes
