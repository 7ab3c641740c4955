// The state behind a Scene: the effective toml::table plus where it came from. Internal to
// the scene layer, so that code using Scene does not compile toml++.
#pragma once
#include <filesystem>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {

struct Scene::Impl {
  toml::table table;
  std::string engine;
  std::filesystem::path source;
  std::vector<std::string> overrides;
  const Schema* schema = nullptr;
  // Keys read through their handles (Scene::get(Key)); a Scene is read by one run at a
  // time, the mutex keeps the record sound if a sink thread reads too.
  mutable std::mutex read_mutex;
  mutable std::set<std::string, std::less<>> read;
};

}  // namespace grainflow::scenes
