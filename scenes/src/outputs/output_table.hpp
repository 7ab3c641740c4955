// The one table of outputs: each row names an output, declares the [output] keys it
// consumes and opens it for a run (nullptr when the scene turns it off). Image outputs
// (PNG, MP4) encode the rendered frames through render's FrameSinks, on threads of their
// own; data outputs receive Snapshots, stats rows and the run record (run_output.hpp).
// Adding an output = one file in outputs/ and one row in output_table.cpp.
#pragma once
#include <memory>
#include <span>
#include <string_view>

#include "render/output/frame_sink.hpp"
#include "scenes/src/outputs/run_output.hpp"

namespace grainflow::scenes {

class Schema;

struct OutputEntry {
  std::string_view name;
  std::string_view description;
  void (*declare_keys)(Schema&);
  // One of the two is set.
  std::unique_ptr<render::FrameSink> (*open_image)(const OutputContext&) = nullptr;
  std::unique_ptr<RunOutput> (*open_data)(const OutputContext&) = nullptr;
};

std::span<const OutputEntry> outputs();

// Declares [output] and every output's keys.
void declare_output_keys(Schema& s);

}  // namespace grainflow::scenes
