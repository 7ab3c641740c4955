#include "render/context/gl_api.hpp"

#include <string>

#include "engine/core/error.hpp"

namespace grainflow::render {

void GlApi::load(ProcLoader loader) {
#define GRAINFLOW_GL_LOAD(type, name)                                                     \
  name = reinterpret_cast<type>(loader("gl" #name));                                      \
  if (!name) throw Error(std::string("OpenGL entry point gl" #name " is not available"));
  GRAINFLOW_GL_FUNCTIONS(GRAINFLOW_GL_LOAD)
#undef GRAINFLOW_GL_LOAD
}

}  // namespace grainflow::render
