#include "scenes/src/run/checkpoints.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "scenes/src/run/run_folder.hpp"

namespace grainflow::scenes {
namespace {

constexpr const char* kSlots[2] = {"checkpoints/checkpoint_0.gfck", "checkpoints/checkpoint_1.gfck"};

}  // namespace

void CheckpointStore::write(io::CheckpointInfo info, std::string_view payload) {
  info.sequence = ++sequence_;
  const char* slot = kSlots[info.sequence % 2];
  folder_.claim(slot);
  io::make_output_folder(folder_.file("checkpoints"));
  io::write_checkpoint(folder_.file(slot), info, payload);
}

io::Checkpoint CheckpointStore::read_latest(std::string_view engine, std::uint64_t scene_fingerprint) {
  std::vector<io::Checkpoint> usable;
  std::vector<std::string> problems;
  for (const char* slot : kSlots) {
    const std::filesystem::path file = folder_.file(slot);
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) continue;
    try {
      io::Checkpoint ck = io::read_checkpoint(file);
      if (ck.info.engine != engine)
        throw Error("checkpoint " + file.string() + " is of the '" + ck.info.engine + "' engine; this scene runs '" +
                    std::string(engine) + "'");
      if (ck.info.scene_fingerprint != scene_fingerprint)
        throw Error("checkpoint " + file.string() + " belongs to another scene (its physics, sampling or render "
                    "keys differ from " + folder_.file("scene.toml").string() + ")");
      usable.push_back(std::move(ck));
    } catch (const Error& e) {
      problems.emplace_back(e.what());
    }
  }
  if (usable.empty()) {
    std::string why = problems.empty() ? "it holds no checkpoint (" + folder_.file("checkpoints").string() +
                                             "/checkpoint_*.gfck; runs write them every output.checkpoint_every "
                                             "and when interrupted)"
                                       : problems.front();
    for (std::size_t i = 1; i < problems.size(); ++i) why += "; " + problems[i];
    throw Error("cannot resume in '" + folder_.dir().string() + "': " + why);
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < usable.size(); ++i)
    if (usable[i].info.sequence > usable[best].info.sequence) best = i;
  // A newer checkpoint that could not be used is worth knowing about.
  for (const auto& p : problems) std::fprintf(stderr, "grainflow: warning: %s; using the other one\n", p.c_str());
  sequence_ = usable[best].info.sequence;
  return std::move(usable[best]);
}

}  // namespace grainflow::scenes
