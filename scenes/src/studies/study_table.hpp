// The one table of studies ([study] kind = "…") and the run output that runs the chosen
// one: it feeds the study the run's stats rows and frames and, at the end, writes
// study.json and study.png into the run folder (claimed, atomically).
#pragma once
#include <memory>
#include <span>

#include "scenes/src/outputs/run_output.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/studies/study.hpp"

namespace grainflow::render {
class GlContext;
}

namespace grainflow::scenes {

std::span<const StudyEntry> studies();
// [study] with kind from the table's studies of `engine`, and their keys; nothing when
// no study reads that engine's stats.
void declare_study_keys(Schema& s, std::string_view engine);
// nullptr when the scene has no [study]. `gl`: the run's context, current on this thread,
// which draws study.png.
std::unique_ptr<RunOutput> open_study_output(const OutputContext& context, render::GlContext& gl);

namespace study_keys {
inline constexpr TableKey study{"study"};
inline constexpr Key<std::string> kind{"study.kind"};
}  // namespace study_keys

}  // namespace grainflow::scenes
