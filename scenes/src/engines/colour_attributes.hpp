// The colour attributes an engine's particles offer to render.color_by: each engine keeps
// one table of rows {name, value function, …} beside its runner (kDiskAttributes,
// kSphereAttributes); these two helpers give the schema its names and the runner its row.
#pragma once
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace grainflow::scenes {

template <class Row> std::vector<std::string> attribute_names(std::span<const Row> rows) {
  std::vector<std::string> names;
  for (const auto& r : rows) names.emplace_back(r.name);
  return names;
}

// The row of `name`; validation has checked it against attribute_names(), so a miss is a
// programming error.
template <class Row> const Row& find_attribute(std::span<const Row> rows, std::string_view name) {
  for (const auto& r : rows)
    if (r.name == name) return r;
  throw std::logic_error("colour attribute '" + std::string(name) + "' passed validation but is not in the table");
}

}  // namespace grainflow::scenes
