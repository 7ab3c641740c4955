// The colour-map tables compiled into the binary (generated into colormap_tables.cpp by
// assets/colormaps/generate.py from assets/colormaps/*.csv). Use Colormap, not this.
#pragma once
#include <string_view>

namespace grainflow::render::colormap_tables {

struct Table {
  std::string_view name;    // user-facing name, e.g. "cool-warm"
  const float (*rgb)[3];    // size entries, r g b in [0, 1]
  int size;
  std::string_view source;  // origin and licence
};

// Order = the order of ColormapId.
inline constexpr int kCount = 6;
extern const Table all[kCount];

}  // namespace grainflow::render::colormap_tables
