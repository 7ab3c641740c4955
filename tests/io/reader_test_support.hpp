// Helpers shared by the particle-reader tests: test data paths, temporary files, and
// every frame of a file read at once.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/io/particle_reader.hpp"

namespace grainflow::io::test {

inline std::string data(const std::string& name) { return std::string(GRAINFLOW_TEST_DATA) + "/particles/" + name; }

inline std::string out_path(const std::string& name) {
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  return std::string(GRAINFLOW_TEST_OUT) + "/" + name;
}

// Writes `text` (bytes as given) under the test output folder; returns the path.
inline std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = out_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline std::vector<core::ParticleFrame> read_all(const std::string& path) {
  auto reader = open_particle_file(path);
  std::vector<core::ParticleFrame> frames;
  core::ParticleFrame f;
  while (reader->next(f)) frames.push_back(f);
  return frames;
}

}  // namespace grainflow::io::test
