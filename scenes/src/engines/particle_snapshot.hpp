// Turns particle data read from a file (core::ParticleFrame) into what the renderer
// draws (render::Snapshot): positions with radii, the colour attribute, the domain.
#pragma once
#include <string>

#include "engine/core/particle_frame.hpp"
#include "render/snapshot.hpp"

namespace grainflow::scenes {

// The attribute `grainflow render` colours by when the user names none: speed when the
// file has velocities, else type when there is more than one, else none (flat colour).
std::string default_colour_attribute(const core::ParticleFrame& frame);

// Box of the frame: its own box when the file has one, else the particles' bounds
// (positions ± radius).
void frame_bounds(const core::ParticleFrame& frame, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

// Fills `out` (reusing its storage). `attribute` may be empty (flat colour); an unknown
// attribute throws grainflow::Error listing the columns the file has.
void to_snapshot(const core::ParticleFrame& frame, const std::string& attribute, render::Snapshot& out);

}  // namespace grainflow::scenes
