// The shaders of assets/shaders/, embedded by render/CMakeLists.txt at configure time.
#pragma once
#include <string_view>
#include <vector>

namespace grainflow::render {

struct EmbeddedShader {
  std::string_view name;  // file name, e.g. "disks.vert"
  std::string_view text;
};

const std::vector<EmbeddedShader>& embedded_shaders();

}  // namespace grainflow::render
